// The cloth nodes through the engine (frames included), and ClothStep frame by
// frame through a host of its own that gives ctx.time().step = 1/fps and feeds
// the previous output back (to see its warnings).
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "cloth_state.hpp"
#include "loom/mesh.hpp"
#include "loom/testing.hpp"
#include "ply_points.hpp"
#include "run_loom.hpp"
#include "test_files.hpp"

namespace {

using loom::cloth::ClothState;

loom::json grid_graph(const loom::json& step_inputs) {
  loom::json step = {{"type", "ClothStep"}, {"inputs", step_inputs}};
  step["inputs"]["state"] = {{"from", "grid.state"}};
  return {{"loom", 1},
          {"nodes",
           {{"grid", {{"type", "MassSpringGrid"}, {"inputs", {{"vertices", {6, 6}}, {"pin", "none"}}}}},
            {"step", step}}}};
}

// Runs a node type's function with given inputs (defaults for the rest) at a
// given frame time, as the engine's simulation contract describes.
class FrameHost : public loom::NodeHost {
 public:
  FrameHost(const loom::NodeSpec& spec, std::map<std::string, loom::Value> values) : spec_(spec) {
    for (size_t i = 0; i < spec.inputs.size(); ++i) {
      const auto& input = spec.inputs[i];
      auto it = values.find(input.name);
      if (it != values.end())
        inputs_.push_back(it->second);
      else if (!input.default_value.is_null())
        inputs_.emplace_back(input.type, input.type->from_json(input.default_value));
      else
        inputs_.emplace_back();
    }
  }
  loom::Value fetch_input(int index) override { return inputs_[static_cast<size_t>(index)]; }
  bool input_set(int index) const override { return static_cast<bool>(inputs_[static_cast<size_t>(index)]); }
  void report_progress(double, std::string_view) override {}
  void report(bool warning, std::string text) override {
    if (warning) warnings.push_back(text);
  }
  bool cancelled() const override { return false; }
  std::shared_ptr<void> scratch(std::uint64_t key, const std::function<std::shared_ptr<void>()>& make) override {
    auto& slot = scratch_[key];
    if (!slot) slot = make();
    return slot;
  }
  std::shared_ptr<void> sequence_state(const std::function<std::shared_ptr<void>()>& make) override {
    if (!sequence_) sequence_ = make();
    return sequence_;
  }
  void set(const std::string& name, loom::Value v) { inputs_[static_cast<size_t>(spec_.input_index(name))] = std::move(v); }
  std::vector<std::string> warnings;

 private:
  const loom::NodeSpec& spec_;
  std::vector<loom::Value> inputs_;
  std::map<std::uint64_t, std::shared_ptr<void>> scratch_;
  std::shared_ptr<void> sequence_;
};

// Frames start..start+frames of a ClothStep from the given initial state.
std::vector<loom::Value> run_frames(loom::testing::Engine& engine, loom::Value initial,
                                    std::map<std::string, loom::Value> inputs, int frames, double fps,
                                    FrameHost** host_out = nullptr) {
  engine.load_plugins({"ClothStep"});
  const loom::NodeType* type = engine.registry().find("ClothStep");
  EXPECT_NE(type, nullptr);
  inputs["state"] = initial;
  static std::unique_ptr<FrameHost> host;
  host = std::make_unique<FrameHost>(type->spec, inputs);
  if (host_out) *host_out = host.get();
  std::vector<loom::Value> states;
  const std::string id = "step";
  const std::filesystem::path dir = ".";
  for (int f = 1; f <= frames + 1; ++f) {
    loom::FrameTime time;
    time.frame = f;
    time.start = 1;
    time.fps = fps;
    time.step = f == 1 ? 0 : 1 / fps;
    loom::Inputs in(type->spec, *host);
    loom::Outputs out(type->spec);
    loom::Context ctx(*host, id, 7, dir, dir, time);
    type->run(in, out, ctx);
    const loom::Value state = out.values()[static_cast<size_t>(type->spec.output_index("state"))];
    states.push_back(state);
    host->set("state", state);
  }
  return states;
}

TEST(ClothNodes, TheStartFrameReturnsTheInitialState) {
  loom::testing::Engine engine;
  const auto doc = grid_graph({});
  const auto& initial = engine.output<ClothState>(doc, "grid.state");
  const auto& first = engine.output<ClothState>(doc, "step.state");
  EXPECT_EQ(first.x, initial.x);
  EXPECT_EQ(first.time, 0);
  const auto& mesh = engine.output<loom::Mesh>(doc, "step.mesh");
  EXPECT_EQ(mesh.vertices(), 36);
  EXPECT_EQ(mesh.faces(), 50);
}

TEST(ClothNodes, FramesOfFreeFallFollowTheDiscreteParabola) {
  loom::testing::Engine engine;
  const loom::Value initial = engine.value(grid_graph({}), "grid.state");
  for (const char* solver : {"local_global", "newton"}) {
    const int frames = 12, substeps = 3;
    const double fps = 24;
    const auto states = run_frames(engine, initial,
                                   {{"solver", loom::Value::make<std::string>(solver)},
                                    {"substeps", loom::Value::make<int>(substeps)}},
                                   frames, fps);
    const auto& last = states.back().as<ClothState>();
    const int n = frames * substeps;
    const double h = 1 / (fps * substeps);
    EXPECT_NEAR(last.time, frames / fps, 1e-12);
    for (int i = 0; i < last.x.rows(); ++i) {
      const double expected = initial.as<ClothState>().x(i, 1) - 9.81 * h * h * n * (n + 1) / 2.0;
      EXPECT_NEAR(last.x(i, 1), expected, 1e-10) << solver;
    }
  }
}

// The same through the engine's frames: the evaluator feeds the state back.
TEST(ClothNodes, EngineFramesFollowTheDiscreteParabola) {
  loom::testing::Engine engine;
  auto doc = grid_graph({{"substeps", 3}});
  doc["time"] = {{"start", 1}, {"end", 13}, {"fps", 24}};
  const loom::Graph g = engine.load(doc);
  loom::EvalOptions options;
  options.targets.push_back(loom::parse_target("step.state"));
  options.frames = loom::FrameRange{1, 13};
  const loom::EvalResult result = engine.session().evaluate(g, options);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result.frames, 13);
  const auto& last = result.outputs.at("step.state").at(0).as<ClothState>();
  const auto& initial = engine.output<ClothState>(grid_graph({}), "grid.state");
  const int n = 12 * 3;
  const double h = 1 / (24.0 * 3);
  EXPECT_NEAR(last.time, 12 / 24.0, 1e-12);
  for (int i = 0; i < last.x.rows(); ++i)
    EXPECT_NEAR(last.x(i, 1), initial.x(i, 1) - 9.81 * h * h * n * (n + 1) / 2.0, 1e-10);
}

TEST(ClothNodes, ExplicitWarnsAboveItsStabilityBoundAndNeverWritesNaN) {
  loom::testing::Engine engine;
  const loom::Value initial = engine.value(grid_graph({}), "grid.state");  // k = 1e5 on 4 g
  FrameHost* host = nullptr;
  try {
    const auto states = run_frames(engine, initial, {{"solver", loom::Value::make<std::string>("explicit")}},
                                   30, 30, &host);
    for (const auto& s : states) EXPECT_TRUE(s.as<ClothState>().x.allFinite());
  } catch (const loom::Error& e) {
    EXPECT_NE(std::string(e.what()).find("stability bound"), std::string::npos) << e.what();
  }
  ASSERT_NE(host, nullptr);
  ASSERT_FALSE(host->warnings.empty());
  EXPECT_NE(host->warnings.front().find("stability bound"), std::string::npos);
}

// Gravity of 1e300 overflows the first step (scripts/probe found its NaN
// residuals printed with exit 0). Through the runner, over frames: the engine's
// output check fails ClothStep naming the output, and the mesh writer
// downstream writes nothing.
TEST(ClothNodes, AnOverflowingStepFailsAtItsOwnOutput) {
  const auto dir = loom::test::temp_dir();
  const loom::json doc = {
      {"loom", 1},
      {"time", {{"start", 1}, {"end", 3}, {"fps", 24}}},
      {"nodes",
       {{"grid", {{"type", "MassSpringGrid"}, {"inputs", {{"vertices", {6, 6}}}}}},
        {"step", {{"type", "ClothStep"},
                  {"inputs", {{"state", {{"from", "grid.state"}}}, {"gravity", {0, -1e300, 0}}}}}},
        {"save", {{"type", "SaveMesh"}, {"inputs", {{"mesh", {{"from", "step.mesh"}}}, {"path", "m{frame:04}.ply"}}}}},
        {"residuals", {{"type", "Print"}, {"inputs", {{"value", {{"from", "step.residuals"}}}}}}}}}};
  std::ofstream(dir / "g.json") << doc.dump();
  std::string out;
  const int rc = loom::test::run_loom("run " + (dir / "g.json").string() + " --out " + (dir / "out").string(), &out);
  EXPECT_EQ(rc, 1) << out;
  EXPECT_NE(out.find("(ClothStep) failed: output \""), std::string::npos) << out;
  EXPECT_NE(out.find("NaN or infinite"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "m0002.ply"));
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "m0001.ply"));  // the start frame is the rest state
}

// A cuboid too large to build is refused before anything is allocated.
TEST(ClothNodes, AnOversizedCuboidIsRefused) {
  loom::testing::Engine engine;
  const loom::json big = {
      {"loom", 1}, {"nodes", {{"box", {{"type", "MassSpringCuboid"}, {"inputs", {{"points", {1024, 1024, 1024}}}}}}}}};
  try {
    engine.value(big, "box.state");
    FAIL() << "a 1024^3 lattice was built";
  } catch (const loom::Error& e) {
    EXPECT_NE(std::string(e.what()).find("2^22"), std::string::npos) << e.what();
  }
}

TEST(ClothNodes, StatesSurviveTheDiskFormat) {
  loom::testing::Engine engine;
  loom::json doc = {{"loom", 1},
                    {"nodes", {{"box", {{"type", "MassSpringCuboid"}, {"inputs", {{"points", {3, 4, 5}}}}}}}}};
  const auto& state = engine.output<ClothState>(doc, "box.state");
  loom::ByteWriter w;
  loom::TypeTraits<ClothState>::write(state, w);
  loom::ByteReader r(w.buffer().data(), w.buffer().size());
  const ClothState back = loom::TypeTraits<ClothState>::read(r);
  EXPECT_TRUE(r.at_end());
  EXPECT_EQ(back.x, state.x);
  EXPECT_EQ(back.system->springs, state.system->springs);
  EXPECT_EQ(back.system->mass, state.system->mass);
  loom::ByteReader truncated(w.buffer().data(), w.buffer().size() / 2);
  EXPECT_THROW(loom::TypeTraits<ClothState>::read(truncated), loom::Error);
}

TEST(ClothNodes, ActionableErrors) {
  loom::testing::Engine engine;
  auto doc = grid_graph({{"sphere_centers", {{0, 0, 0}}}, {"sphere_radii", loom::json::array()}});
  EXPECT_THROW(engine.value(doc, "step.state"), loom::Error);
  // Two accelerations of the same iteration: the user is asked to choose one.
  EXPECT_NO_THROW(engine.value(grid_graph({{"anderson", 6}}), "step.state"));
  EXPECT_THROW(engine.value(grid_graph({{"chebyshev", true}, {"anderson", 6}}), "step.state"), loom::Error);
  doc = grid_graph({});
  doc["nodes"]["grid"]["inputs"]["fixed"] = {1000};
  EXPECT_THROW(engine.value(doc, "grid.state"), loom::Error);
  doc = {{"loom", 1},
         {"nodes",
          {{"pts", {{"type", "GridMesh"}, {"inputs", {{"resolution", {3, 3}}}}}},
           {"ms", {{"type", "MassSpringMesh"}, {"inputs", {{"mesh", {{"from", "pts.mesh"}}}, {"area_density", 0.5}}}}}}}};
  const auto& state = engine.output<ClothState>(doc, "ms.state");
  EXPECT_NEAR(state.system->mass.sum(), 0.5, 1e-12);  // GridMesh is 1 × 1
}

// UVs (and colors) survive simulation: a GridMesh's UVs are the simulated
// mesh's at every frame, and MassSpringGrid's are (i/(nx−1), j/(ny−1)).
TEST(ClothNodes, UVsFollowTheClothThroughSimulatedFrames) {
  loom::testing::Engine engine;
  loom::json doc = {
      {"loom", 1},
      {"time", {{"start", 1}, {"end", 4}, {"fps", 30}}},
      {"nodes",
       {{"sheet", {{"type", "GridMesh"}, {"inputs", {{"resolution", {4, 3}}, {"center", {0, 1, 0}}}}}},
        {"ms", {{"type", "MassSpringMesh"},
                {"inputs", {{"mesh", {{"from", "sheet.mesh"}}}, {"fixed_box_min", {-1, 1.4, -1}}, {"fixed_box_max", {1, 2, 1}}}}}},
        {"grid", {{"type", "MassSpringGrid"}, {"inputs", {{"vertices", {5, 4}}}}}},
        {"a", {{"type", "ClothStep"}, {"inputs", {{"state", {{"from", "ms.state"}}}}}}},
        {"b", {{"type", "ClothStep"}, {"inputs", {{"state", {{"from", "grid.state"}}}}}}}}}};
  const loom::Graph g = engine.load(doc);
  loom::EvalOptions options;
  for (const char* t : {"a.mesh", "b.mesh", "sheet.mesh"}) options.targets.push_back(loom::parse_target(t));
  options.frames = loom::FrameRange{1, 4};
  const loom::EvalResult result = engine.session().evaluate(g, options);
  ASSERT_TRUE(result.ok());
  const auto& sheet = result.outputs.at("sheet.mesh").back().as<loom::Mesh>();
  const auto& a = result.outputs.at("a.mesh").back().as<loom::Mesh>();
  const auto& b = result.outputs.at("b.mesh").back().as<loom::Mesh>();
  ASSERT_TRUE(sheet.has_uv());
  EXPECT_EQ(a.UV, sheet.UV);
  EXPECT_GT((a.V - sheet.V).norm(), 1e-6);  // it moved (a little: k = 1e5 on 1 m²)
  ASSERT_TRUE(b.has_uv());
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 5; ++i) {
      EXPECT_EQ(b.UV(j * 5 + i, 0), i / 4.0);
      EXPECT_EQ(b.UV(j * 5 + i, 1), j / 3.0);
    }
  // The disk format keeps them.
  const ClothState state = engine.output<ClothState>(doc, "ms.state");
  loom::ByteWriter w;
  loom::TypeTraits<ClothState>::write(state, w);
  loom::ByteReader r(w.buffer().data(), w.buffer().size());
  EXPECT_EQ(loom::TypeTraits<ClothState>::read(r).system->UV, sheet.UV);
}

// Placement: rotating by 90° about z maps (x, y, z) to (−y, x, z) (written out
// here, not through the node's rotation), then the translation; the fixed box
// is given in the placed (world) coordinates.
TEST(ClothNodes, PlacementRotatesAndMovesBeforeFixing) {
  loom::testing::Engine engine;
  const loom::json doc = {
      {"loom", 1},
      {"nodes",
       {{"sheet", {{"type", "GridMesh"}, {"inputs", {{"resolution", {2, 2}}, {"size", {2, 1}}}}}},
        {"moved", {{"type", "GridMesh"},
                   {"inputs", {{"resolution", {2, 2}}, {"size", {2, 1}}, {"center", {1, 2, 3}}, {"rotate_degrees", {0, 0, 90}}}}}},
        {"ms", {{"type", "MassSpringMesh"},
                {"inputs", {{"mesh", {{"from", "sheet.mesh"}}}, {"translate", {1, 2, 3}}, {"rotate_degrees", {0, 0, 90}},
                            {"fixed_box_min", {0, 2.9, 0}}, {"fixed_box_max", {2, 4, 4}}}}}},
        {"grid", {{"type", "MassSpringGrid"},
                  {"inputs", {{"vertices", {3, 2}}, {"size", {2, 1}}, {"center", {1, 2, 3}}, {"rotate_degrees", {0, 90, 0}}}}}}}}};
  const auto& sheet = engine.output<loom::Mesh>(doc, "sheet.mesh");
  const auto& moved = engine.output<loom::Mesh>(doc, "moved.mesh");
  const auto& placed = engine.output<ClothState>(doc, "ms.state");
  for (int i = 0; i < sheet.vertices(); ++i) {
    const Eigen::RowVector3d expected(1 - sheet.V(i, 1), 2 + sheet.V(i, 0), 3 + sheet.V(i, 2));
    EXPECT_LT((moved.V.row(i) - expected).norm(), 1e-12) << i;
    EXPECT_LT((placed.x.row(i) - expected).norm(), 1e-12) << i;
    EXPECT_EQ(placed.system->fixed[i], expected.y() >= 2.9 ? 1 : 0) << i;  // the sheet's x = +1 edge
  }
  EXPECT_EQ(placed.system->fixed_count(), 3);
  // MassSpringGrid turned 90° about y about its center: u along x becomes −z.
  const auto& grid = engine.output<ClothState>(doc, "grid.state");
  EXPECT_LT((grid.x.row(0) - Eigen::RowVector3d(1, 1.5, 4)).norm(), 1e-12);
  EXPECT_LT((grid.x.row(2) - Eigen::RowVector3d(1, 1.5, 2)).norm(), 1e-12);
}

// ClothPoints → SavePoints: the state's velocities and masses in a PLY, read
// back (tests/support's reader) and compared with the step's state exactly.
TEST(ClothNodes, VelocitiesWrittenAsPointsReadBackExactly) {
  loom::testing::Engine engine;
  loom::json doc = grid_graph({{"wind_speed", 3.0}});
  doc["time"] = {{"start", 1}, {"end", 3}, {"fps", 30}};
  doc["nodes"]["pts"] = {{"type", "ClothPoints"}, {"inputs", {{"state", {{"from", "step.state"}}}}}};
  doc["nodes"]["save"] = {{"type", "SavePoints"},
                          {"inputs", {{"points", {{"from", "pts.points"}}}, {"path", "cloth_{frame:04}.ply"}, {"double_precision", true}}}};
  const loom::Graph g = engine.load(doc);
  loom::EvalOptions options;
  options.targets.push_back(loom::parse_target("save"));
  options.targets.push_back(loom::parse_target("step.state"));
  options.frames = loom::FrameRange{1, 3};
  options.output_dir = loom::test::temp_dir();
  const loom::EvalResult result = engine.session().evaluate(g, options);
  ASSERT_TRUE(result.ok());
  const auto& state = result.outputs.at("step.state").back().as<ClothState>();
  const loom::test::PlyPoints ply = loom::test::read_ply_points(options.output_dir / "cloth_0003.ply");
  ASSERT_EQ(ply.count, state.x.rows());
  const char* v[] = {"velocity_x", "velocity_y", "velocity_z"};
  for (int i = 0; i < state.x.rows(); ++i) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(ply.columns.at(v[k])[i], state.v(i, k)) << i;
    EXPECT_EQ(ply.columns.at("mass")[i], state.system->mass[i]);
    EXPECT_EQ(ply.columns.at("fixed")[i], state.system->fixed[i]);
  }
  // It fell: (x_3 − x_2)/h is the velocity the file holds.
  EXPECT_LT(ply.columns.at("velocity_y")[0], -0.1);
}

}  // namespace
