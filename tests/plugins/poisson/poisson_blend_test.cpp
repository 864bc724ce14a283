// PoissonBlend through the engine: region inputs, errors a user sees, caching.
#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "loom/image.hpp"
#include "loom/testing.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

json graph_with(const json& blend_inputs) {
  json inputs = {{"source", {{"from", "source.image"}}}, {"target", {{"from", "target.image"}}}};
  inputs.update(blend_inputs);
  return {{"loom", 1},
          {"nodes",
           {{"target", {{"type", "Checkerboard"}, {"inputs", {{"size", {160, 120}}, {"cells", 3}}}}},
            {"source",
             {{"type", "Checkerboard"},
              {"inputs", {{"size", {64, 64}}, {"cells", 8}, {"color_a", {0.9, 0.5, 0.1}}}}}},
            {"blend", {{"type", "PoissonBlend"}, {"inputs", inputs}}}}}};
}

std::string failure(testing::Engine& engine, const json& doc) {
  testing::Run r = engine.run(doc, {"blend.image"});
  return r.error("blend");
}

TEST(PoissonBlend, PolygonRegionBlendsAndLeavesTheRestAlone) {
  testing::Engine engine;
  const json doc = graph_with({{"polygon", {{32, 4}, {60, 56}, {4, 56}}}, {"offset", {40, 30}}});
  const Image out = engine.output<Image>(doc, "blend.image");
  const Image target = engine.output<Image>(doc, "target.image");
  ASSERT_EQ(out.pixels.size(), target.pixels.size());
  EXPECT_EQ(out.encoding, target.encoding);
  EXPECT_NO_THROW(require_finite(out, "blend"));
  cv::Mat diff = cv::abs(out.pixels - target.pixels);
  EXPECT_EQ(cv::norm(diff(cv::Rect(0, 0, 40, 120)), cv::NORM_INF), 0.0);  // left of the region
  EXPECT_GT(cv::norm(diff, cv::NORM_INF), 0.01);                          // and a change inside
}

TEST(PoissonBlend, RectangleMaskAndSolversAgree) {
  testing::Engine engine;
  const Image mg =
      engine.output<Image>(graph_with({{"rectangle", {8, 8, 40, 30}}, {"offset", {50, 40}}}), "blend.image");
  const Image exact = engine.output<Image>(
      graph_with({{"rectangle", {8, 8, 40, 30}}, {"offset", {50, 40}}, {"solver", "cholmod"}}), "blend.image");
  EXPECT_LT(cv::norm(mg.pixels, exact.pixels, cv::NORM_INF), 0.5 / 255);
}

TEST(PoissonBlend, MaskImageRegion) {
  const auto dir = test::temp_dir();
  cv::Mat mask = cv::Mat::zeros(64, 64, CV_8UC1);
  cv::circle(mask, {32, 32}, 20, 255, cv::FILLED);
  ASSERT_TRUE(cv::imwrite((dir / "mask.png").string(), mask));
  testing::Engine engine;
  json doc = graph_with({{"mask", {{"from", "mask.image"}}}, {"offset", {40, 30}}});
  doc["nodes"]["mask"] = {{"type", "LoadImage"}, {"inputs", {{"path", (dir / "mask.png").string()}, {"decode", "keep"}}}};
  const Image out = engine.output<Image>(doc, "blend.image");
  EXPECT_NO_THROW(require_finite(out, "blend"));
  // A mask of another size than the source.
  cv::Mat small = cv::Mat::zeros(10, 10, CV_8UC1);
  ASSERT_TRUE(cv::imwrite((dir / "small.png").string(), small));
  doc["nodes"]["mask"]["inputs"]["path"] = (dir / "small.png").string();
  EXPECT_NE(failure(engine, doc).find("must match"), std::string::npos);
}

TEST(PoissonBlend, RegionInputsMustBeExactlyOne) {
  testing::Engine engine;
  EXPECT_NE(failure(engine, graph_with(json::object())).find("exactly one"), std::string::npos);
  EXPECT_NE(failure(engine, graph_with({{"rectangle", {1, 1, 5, 5}}, {"polygon", {{1, 1}, {5, 1}, {3, 4}}}}))
                .find("exactly one"),
            std::string::npos);
}

TEST(PoissonBlend, UserErrorsAreClear) {
  testing::Engine engine;
  EXPECT_NE(failure(engine, graph_with({{"rectangle", {100, 100, 5, 5}}})).find("mask is empty"),
            std::string::npos);  // outside the source: nothing left
  EXPECT_NE(failure(engine, graph_with({{"rectangle", {8, 8, 10, 10}}, {"offset", {500, 0}}}))
                .find("outside the target"),
            std::string::npos);
}

TEST(PoissonBlend, NaNPixelsAreAClearError) {
  if (!cv::haveImageWriter(".exr")) GTEST_SKIP() << "OpenCV built without OpenEXR";
  const auto dir = test::temp_dir();
  cv::Mat img(64, 64, CV_32FC3, cv::Scalar::all(0.5));
  img.at<cv::Vec3f>(10, 10)[1] = NAN;
  try {
    if (!cv::imwrite((dir / "nan.exr").string(), img)) GTEST_SKIP() << "cannot write EXR";
  } catch (const cv::Exception&) {
    GTEST_SKIP() << "cannot write EXR";
  }
  testing::Engine engine;
  json doc = graph_with({{"rectangle", {8, 8, 20, 20}}, {"offset", {40, 30}}});
  doc["nodes"]["source"] = {{"type", "LoadImage"}, {"inputs", {{"path", (dir / "nan.exr").string()}}}};
  testing::Run r = engine.run(doc, {"blend.image"});
  EXPECT_EQ(r.status("blend"), NodeStatus::skipped);
  const std::string& error = r.error("source");  // refused where it enters, naming the file
  EXPECT_NE(error.find("nan.exr has NaN or infinite pixels"), std::string::npos) << error;
}

TEST(PoissonBlend, DragReusesTheCachedFactorization) {
  testing::Engine engine;
  json doc = graph_with({{"rectangle", {4, 4, 50, 50}}, {"offset", {20, 20}}, {"solver", "cholmod"}});
  const Graph g1 = engine.load(doc);
  testing::Run r1 = engine.run(g1, {"blend.image"});
  ASSERT_TRUE(r1.ok());
  doc["nodes"]["blend"]["inputs"]["offset"] = {21, 22};
  testing::Run r2 = engine.run(doc, {"blend.image"});
  ASSERT_TRUE(r2.ok());
  EXPECT_EQ(r2.status("blend"), NodeStatus::ran);
  EXPECT_LT(r2.result().nodes.at("blend").seconds, r1.result().nodes.at("blend").seconds);
}

TEST(PoissonBlend, DragResultDoesNotDependOnTheDragHistory) {
  // The multigrid solve starts from the previous correction of the cached
  // hierarchy: the same offset must give the same image (to half a level, and
  // to half a level of the exact solve) whether reached directly or by a drag.
  auto doc_at = [](int x, int y, const char* solver) {
    json doc = graph_with({{"rectangle", {4, 4, 180, 150}}, {"offset", {x, y}}, {"solver", solver}});
    doc["nodes"]["target"]["inputs"]["size"] = {320, 300};
    doc["nodes"]["source"]["inputs"]["size"] = {200, 200};
    doc["nodes"]["source"]["inputs"]["cells"] = 13;
    return doc;
  };
  testing::Engine direct, dragged;
  const Image first = direct.output<Image>(doc_at(60, 70, "multigrid"), "blend.image");
  for (const auto& o : {std::pair{61, 70}, {63, 72}, {20, 100}, {59, 69}})
    ASSERT_TRUE(dragged.run(doc_at(o.first, o.second, "multigrid"), {"blend.image"}).ok());
  const Image after = dragged.output<Image>(doc_at(60, 70, "multigrid"), "blend.image");
  const Image exact = direct.output<Image>(doc_at(60, 70, "cholmod"), "blend.image");
  EXPECT_LT(cv::norm(first.pixels, after.pixels, cv::NORM_INF), 0.5 / 255);
  EXPECT_LT(cv::norm(after.pixels, exact.pixels, cv::NORM_INF), 0.5 / 255);
  EXPECT_LT(cv::norm(first.pixels, exact.pixels, cv::NORM_INF), 0.5 / 255);
}

}  // namespace
}  // namespace loom
