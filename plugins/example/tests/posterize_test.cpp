// Tests of Posterize written with loom::testing, the way an out-of-tree
// plugin tests itself: run the node through a real graph, check its output
// against values worked out by hand, and check what a user sees on bad input.
#include <gtest/gtest.h>

#include "loom/image.hpp"
#include "loom/testing.hpp"

namespace {

using loom::testing::GraphBuilder;

// A 64x64 checkerboard (from the generate plugin installed with Loom) into
// Posterize. Its colors are (0.95, 0.95, 0.95) and (0.15, 0.3, 0.6), sRGB.
GraphBuilder posterized(int levels) {
  GraphBuilder g;
  g.node("board", "Checkerboard").set("size", {64, 64}).set("cells", 2);
  g.node("poster", "Posterize").link("image", "board.image").set("levels", levels);
  return g;
}

TEST(Posterize, TwoLevelsRoundEachChannelToZeroOrOne) {
  loom::testing::Engine engine;
  loom::testing::Run run = engine.run(posterized(2), {"poster.image"});
  ASSERT_TRUE(run.ok()) << run.errors();
  EXPECT_EQ(run.status("poster"), loom::NodeStatus::ran);

  const loom::Image& image = run.output<loom::Image>("poster.image");
  ASSERT_EQ(image.width(), 64);
  ASSERT_EQ(image.channels(), 3);
  EXPECT_EQ(image.encoding, loom::Encoding::srgb);  // the input's tag is kept
  // Corner square: 0.95 rounds up; the other: 0.15, 0.3 down and 0.6 up.
  EXPECT_EQ(image.pixels.at<cv::Vec3f>(0, 0), cv::Vec3f(1, 1, 1));
  EXPECT_EQ(image.pixels.at<cv::Vec3f>(0, 40), cv::Vec3f(0, 0, 1));
}

TEST(Posterize, FiveLevelsGiveQuarterSteps) {
  loom::testing::Engine engine;
  const loom::Image image = engine.output<loom::Image>(posterized(5), "poster.image");
  // round(c * 4) / 4: 0.95 -> 1, 0.15 -> 0.25, 0.3 -> 0.25, 0.6 -> 0.5.
  EXPECT_EQ(image.pixels.at<cv::Vec3f>(63, 63), cv::Vec3f(1, 1, 1));
  EXPECT_EQ(image.pixels.at<cv::Vec3f>(10, 50), cv::Vec3f(0.25f, 0.25f, 0.5f));
}

TEST(Posterize, PosterizingTwiceChangesNothing) {
  GraphBuilder g = posterized(3);
  g.node("again", "Posterize").link("image", "poster.image").set("levels", 3);
  loom::testing::Engine engine;
  loom::testing::Run run = engine.run(g, {"poster.image", "again.image"});
  ASSERT_TRUE(run.ok()) << run.errors();
  const cv::Mat once = run.output<loom::Image>("poster.image").pixels;
  const cv::Mat twice = run.output<loom::Image>("again.image").pixels;
  EXPECT_EQ(cv::norm(once, twice, cv::NORM_INF), 0.0);
}

TEST(Posterize, SecondRunComesFromTheCache) {
  loom::testing::Engine engine;
  ASSERT_TRUE(engine.run(posterized(4), {"poster.image"}).ok());
  EXPECT_EQ(engine.run(posterized(4), {"poster.image"}).status("poster"), loom::NodeStatus::cached);
}

TEST(Posterize, LevelsOutOfRangeIsAGraphErrorNamingTheInput) {
  loom::testing::Engine engine;
  try {
    engine.run(posterized(1));
    FAIL() << "levels = 1 was accepted";
  } catch (const loom::GraphError& e) {
    EXPECT_NE(std::string(e.what()).find("/nodes/poster/inputs/levels"), std::string::npos) << e.what();
  }
}

TEST(Posterize, AGraphFromJsonWorksTheSame) {
  loom::testing::Engine engine;
  const loom::json graph = loom::json::parse(R"({"loom": 1, "nodes": {
    "board": {"type": "Checkerboard", "inputs": {"size": [8, 8], "cells": 1}},
    "poster": {"type": "Posterize", "inputs": {"image": {"from": "board.image"}, "levels": 2}}}})");
  const loom::Image image = engine.output<loom::Image>(graph, "poster.image");
  EXPECT_EQ(image.pixels.at<cv::Vec3f>(7, 7), cv::Vec3f(1, 1, 1));
  EXPECT_EQ(engine.loaded_plugins(), (std::vector<std::string>{"generate", "example"}));
}

}  // namespace
