// The mpm plugin's nodes through the engine, and the state's serialization.
#include <gtest/gtest.h>

#include "loom/image.hpp"
#include "loom/point_set.hpp"
#include "loom/polylines.hpp"
#include "loom/testing.hpp"
#include "mpm_scenes.hpp"
#include "mpm_state.hpp"

namespace {

using loom::mpm::MpmState;

loom::json box_graph(const loom::json& emit_inputs) {
  loom::json emit = {{"type", "MPMEmitBox"}, {"inputs", emit_inputs}};
  return {{"loom", 1},
          {"nodes",
           {{"emit", emit},
            {"sim", {{"type", "MPMStep"}, {"inputs", {{"state", {{"from", "emit.particles"}}}}}}},
            {"image",
             {{"type", "MPMSplat"},
              {"inputs", {{"state", {{"from", "sim.state"}}}, {"width", 64}}}}}}}};
}

TEST(MpmNodes, BoxOnALatticeHasTheExactCountAndVolume) {
  loom::testing::Engine engine;
  const auto doc = box_graph({{"min", {0.2, 0.2, 0}}, {"max", {0.4, 0.5, 0}}, {"sampling", "grid"},
                              {"spacing", 0.01}, {"density", 2.0}});
  const auto& state = engine.output<MpmState>(doc, "emit.particles");
  ASSERT_EQ(state.dim, 2);
  ASSERT_EQ(state.size(), 20 * 30);
  for (int i = 0; i < state.size(); ++i) {
    EXPECT_NEAR(state.p2.volume[i], 1e-4, 1e-15);
    EXPECT_NEAR(state.p2.mass[i], 2e-4, 1e-15);
  }
  // At the start frame the step advances by nothing: the state passes through.
  const auto& stepped = engine.output<MpmState>(doc, "sim.state");
  EXPECT_EQ(stepped.substeps, 0);
  EXPECT_EQ(stepped.p2.x, state.p2.x);
  const auto& points = engine.output<loom::PointSet>(doc, "sim.points");
  EXPECT_EQ(points.points(), state.size());
  EXPECT_TRUE(points.has_colors());
  EXPECT_EQ(points.P.col(2).cwiseAbs().maxCoeff(), 0.0);
  const auto& image = engine.output<loom::Image>(doc, "image.image");
  EXPECT_EQ(image.pixels.cols, 64);
  EXPECT_EQ(image.pixels.rows, 64);
}

TEST(MpmNodes, MeshEmitterFillsTheInsideOfASphere) {
  loom::testing::Engine engine;
  const loom::json doc = {
      {"loom", 1},
      {"nodes",
       {{"sphere", {{"type", "UVSphere"}, {"inputs", {{"radius", 1.0}, {"rings", 24}, {"segments", 48}}}}},
        {"emit",
         {{"type", "MPMEmitMesh"},
          {"inputs",
           {{"mesh", {{"from", "sphere.mesh"}}}, {"dimension", 3}, {"scale", 0.1},
            {"translate", {0.5, 0.5, 0.5}}, {"spacing", 0.01}, {"sampling", "grid"}}}}}}}};
  const auto& state = engine.output<MpmState>(doc, "emit.particles");
  ASSERT_EQ(state.dim, 3);
  const double ball = 4.0 / 3 * M_PI * 1e-3 / 1e-6;  // particles in the ball at spacing 0.01
  EXPECT_NEAR(state.size(), ball, 0.05 * ball);
  for (const auto& x : state.p3.x) EXPECT_LE((x - Eigen::Vector3d::Constant(0.5)).norm(), 0.1 + 1e-9);
}

TEST(MpmNodes, ActionableErrors) {
  loom::testing::Engine engine;
  auto doc = box_graph({{"spacing", 10.0}, {"sampling", "grid"}});
  // A box smaller than one spacing still gets one lattice point; a tiny box not:
  doc["nodes"]["emit"]["inputs"]["min"] = {0.2, 0.2, 0};
  doc["nodes"]["emit"]["inputs"]["max"] = {0.2, 0.3, 0};
  EXPECT_THROW(engine.value(doc, "emit.particles"), loom::Error);
  doc = box_graph({});
  doc["nodes"]["sim"]["inputs"]["colliders"] = {{{"shape", "cone"}}};
  EXPECT_THROW(engine.value(doc, "sim.state"), loom::Error);
  doc["nodes"]["sim"]["inputs"]["colliders"] = {{{"shape", "sphere"}, {"center", {0.5, 0.5}}}};
  EXPECT_THROW(engine.value(doc, "sim.state"), loom::Error);
  const loom::json mesh2d = {
      {"loom", 1},
      {"nodes",
       {{"sphere", {{"type", "UVSphere"}, {"inputs", loom::json::object()}}},
        {"emit", {{"type", "MPMEmitMesh"}, {"inputs", {{"mesh", {{"from", "sphere.mesh"}}}}}}}}}};
  EXPECT_THROW(engine.value(mesh2d, "emit.particles"), loom::Error);
}

TEST(MpmNodes, NBodyLandsASlowShipAndKeepsEnergy) {
  loom::testing::Engine engine;
  const loom::json doc = {
      {"loom", 1},
      {"nodes",
       {{"slow", {{"type", "NBody"},
                  {"inputs", {{"velocities", {{0, 0, 0}, {0, 0.3, 0}}}, {"central_radius", 0.3},
                              {"duration", 5.0}}}}},
        {"orbit", {{"type", "NBody"}, {"inputs", {{"duration", 20.0}, {"integrator", "leapfrog"}}}}}}}};
  const auto events = engine.output<loom::json>(doc, "slow.events");
  ASSERT_EQ(events["landed"].size(), 1u);
  EXPECT_EQ(events["landed"][0]["body"], 1);
  EXPECT_LT(engine.output<double>(doc, "orbit.energy_error"), 1e-6);
  const auto& lines = engine.output<loom::Polylines>(doc, "orbit.trajectories");
  EXPECT_EQ(lines.vertices(), 2 * 2000);
  // The circular orbit (v = 1 at r = 1) stays on the unit circle.
  for (int i = 2000; i < 4000; ++i) EXPECT_NEAR(lines.P.row(i).norm(), 1, 1e-6);
}

// A huge planet or a tiny extent put pixel coordinates beyond int: they are
// clamped far outside the canvas instead of overflowing into OpenCV's asserts
// (found by scripts/probe). The huge planet covers the whole canvas.
TEST(MpmNodes, OrbitPlotKeepsExtremeScalesOnTheCanvas) {
  loom::testing::Engine engine;
  for (const auto& [radius, extent] : {std::pair{1e9, 3.0}, std::pair{1e300, 3.0}, std::pair{0.2, 1e-300}}) {
    const loom::json doc = {
        {"loom", 1},
        {"nodes",
         {{"orbit", {{"type", "NBody"}, {"inputs", {{"duration", 1.0}, {"samples", 16}}}}},
          {"plot", {{"type", "OrbitPlot"},
                    {"inputs", {{"a", {{"from", "orbit.trajectories"}}}, {"planet_radius", radius},
                                {"extent", extent}, {"width", 64}}}}}}}};
    const auto& image = engine.output<loom::Image>(doc, "plot.image");
    ASSERT_EQ(image.width(), 64);
    if (radius > 1e6) {  // the planet's colour (200, 140, 70) in BGR fills the corner pixel
      const cv::Vec3f corner = image.pixels.at<cv::Vec3f>(0, 0);
      EXPECT_NEAR(corner[0], 70 / 255.0, 1e-6);
      EXPECT_NEAR(corner[2], 200 / 255.0, 1e-6);
    }
  }
}

TEST(MpmState, WriteReadRoundTrip) {
  MpmState s;
  s.dim = 2;
  s.p2 = loom::mpm::test::mpm88(100);
  s.time = 0.5;
  s.substeps = 7;
  loom::ByteWriter w;
  loom::TypeTraits<MpmState>::write(s, w);
  loom::ByteReader r(w.buffer().data(), w.buffer().size());
  const MpmState t = loom::TypeTraits<MpmState>::read(r);
  EXPECT_TRUE(r.at_end());
  EXPECT_EQ(t.dim, 2);
  EXPECT_EQ(t.time, 0.5);
  EXPECT_EQ(t.substeps, 7);
  EXPECT_EQ(t.p2.x, s.p2.x);
  EXPECT_EQ(t.p2.mass, s.p2.mass);
  EXPECT_EQ(t.p2.material, s.p2.material);
  // Truncated bytes are an error, never a crash.
  loom::ByteReader cut(w.buffer().data(), w.buffer().size() / 2);
  EXPECT_THROW(loom::TypeTraits<MpmState>::read(cut), loom::Error);
}

}  // namespace
