// MPMStep through the engine's frames: the state fed back frame after frame
// equals a hand-written loop over the solver library, bit for bit.
#include <gtest/gtest.h>

#include "emitters.hpp"
#include "loom/testing.hpp"
#include "mls_mpm.hpp"
#include "mpm_state.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

TEST(MpmFrames, TheEngineFeedsTheStateBackLikeAHandWrittenLoop) {
  testing::Engine e;
  const json doc = {
      {"loom", 1},
      {"time", {{"start", 1}, {"end", 11}, {"fps", 50}}},
      {"nodes",
       {{"emit", {{"type", "MPMEmitBox"},
                  {"inputs", {{"min", {0.3, 0.5, 0}}, {"max", {0.5, 0.7, 0}}, {"material", "elastic"},
                              {"E", 1000.0}, {"sampling", "grid"}, {"spacing", 1.0 / 128}}}}},
        {"sim", {{"type", "MPMStep"},
                 {"inputs", {{"state", {{"from", "emit.particles"}}}, {"resolution", 64}}}}}}}};
  Graph g = e.load(doc);
  EvalOptions o;
  o.targets.push_back(parse_target("sim.state"));
  o.targets.push_back(parse_target("sim.substeps"));
  o.frames = FrameRange{1, 11};
  o.output_dir = test::temp_dir();
  EvalResult r = e.session().evaluate(g, o);
  ASSERT_TRUE(r.ok());
  const auto& state = r.outputs.at("sim.state").at(0).as<mpm::MpmState>();
  EXPECT_NEAR(state.time, 10 / 50.0, 1e-12);
  EXPECT_GT(r.outputs.at("sim.substeps").at(0).as<int>(), 0);

  // The same by hand: the emitter's lattice, ten advances of 1/50 s.
  mpm::EmitOptions eo;
  eo.material = mpm::Material::elastic;
  eo.E = 1000;
  eo.sampling = mpm::Sampling::grid;
  eo.spacing = 1.0 / 128;
  auto ps = mpm::fill_shape<2>([](const Eigen::Vector2d&) { return true; }, Eigen::Vector2d(0.3, 0.5),
                               Eigen::Vector2d(0.5, 0.7), eo);
  mpm::Settings s;
  s.resolution = 64;
  for (int f = 2; f <= 11; ++f) mpm::Solver<2>(s).advance(ps, 1 / 50.0);
  ASSERT_EQ(state.p2.size(), ps.size());
  EXPECT_EQ(state.p2.x, ps.x);
  EXPECT_EQ(state.p2.F, ps.F);
}

}  // namespace
}  // namespace loom
