// Groups and Repeat (issue 25). References are independent of the group
// code: the same computation wired by hand as a flat graph (version 1, ids
// written out), hand-written loops, and counts of the runs the engine reports.
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>

#include "loom/image.hpp"
#include "loom/mesh.hpp"
#include "loom/testing.hpp"

namespace loom {
namespace {

namespace fs = std::filesystem;

json link(const std::string& from) { return {{"from", from}}; }

// A folder of group files, removed at the end.
struct Folder {
  fs::path dir;
  Folder() {
    std::string pattern = (fs::temp_directory_path() / "loom-groups-XXXXXX").string();
    dir = ::mkdtemp(pattern.data());
  }
  ~Folder() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  fs::path write(const std::string& name, const json& doc) const {
    fs::create_directories((dir / name).parent_path());
    std::ofstream(dir / name) << doc.dump(2);
    return dir / name;
  }
};

// A graph loaded and validated, evaluated by a session of its own at each
// frame of `frames`; returns target -> value (as JSON) per frame.
std::vector<json> values_per_frame(testing::Engine& engine, const json& doc, const fs::path& file,
                                   const std::vector<std::string>& targets, int first, int last) {
  const Graph g = engine.load(doc, file);
  Session session(engine.registry());
  std::vector<json> frames;
  for (int f = first; f <= last; ++f) {
    EvalOptions o;
    for (const auto& t : targets) o.targets.push_back(parse_target(t));
    o.frames = FrameRange{f, f};
    const EvalResult r = session.evaluate(g, o);
    EXPECT_TRUE(r.ok());
    json row = json::object();
    for (const auto& [name, values] : r.outputs) row[name] = values.at(0).to_json();
    frames.push_back(row);
  }
  return frames;
}

// Inline group "Drift": a simulation (x += v·step) plus a time-dependent
// offset, inside a group used twice with different velocities.
json drift_grouped() {
  json group = {{"description", "x(t) + frame * scale"},
                {"inputs", {{"v", {{"type", "Float"}, {"default", 1.0}, {"to", {"sim.v"}}}},
                            {"scale", {{"type", "Float"}, {"default", 0.5}, {"to", {"clock.scale"}}}}}},
                {"outputs", {{"x", {{"from", "sum.result"}}}}},
                {"nodes", {{"sim", {{"type", "Integrate"}}},
                           {"clock", {{"type", "FrameNumber"}}},
                           {"sum", {{"type", "Math"}, {"inputs", {{"a", link("sim.x")}, {"b", link("clock.value")}}}}}}}};
  return {{"loom", 2}, {"time", {{"start", 1}, {"end", 6}, {"fps", 4}}},
          {"groups", {{"Drift", group}}},
          {"nodes", {{"slow", {{"type", "Drift"}, {"inputs", {{"v", 0.25}}}}},
                     {"fast", {{"type", "Drift"}, {"inputs", {{"v", 3.0}, {"scale", 2.0}}}}},
                     {"both", {{"type", "Math"}, {"inputs", {{"a", link("slow.x")}, {"b", link("fast.x")}, {"op", "multiply"}}}}}}}};
}

json drift_flat() {
  json nodes = json::object();
  for (const auto& [id, v, scale] : {std::tuple{"slow", 0.25, 0.5}, std::tuple{"fast", 3.0, 2.0}}) {
    const std::string p = id;
    nodes[p + "_sim"] = {{"type", "Integrate"}, {"inputs", {{"v", v}}}};
    nodes[p + "_clock"] = {{"type", "FrameNumber"}, {"inputs", {{"scale", scale}}}};
    nodes[p + "_sum"] = {{"type", "Math"}, {"inputs", {{"a", link(p + "_sim.x")}, {"b", link(p + "_clock.value")}}}};
  }
  nodes["both"] = {{"type", "Math"}, {"inputs", {{"a", link("slow_sum.result")}, {"b", link("fast_sum.result")}, {"op", "multiply"}}}};
  return {{"loom", 1}, {"time", {{"start", 1}, {"end", 6}, {"fps", 4}}}, {"nodes", nodes}};
}

TEST(Groups, AGroupedGraphEqualsItsFlatFormOverATimeRangeWithASimulationInside) {
  testing::Engine engine({LOOM_TEST_PLUGIN_DIR});
  const auto grouped = values_per_frame(engine, drift_grouped(), "g.json", {"both.result", "slow.x"}, 1, 6);
  const auto flat = values_per_frame(engine, drift_flat(), "f.json", {"both.result", "slow_sum.result"}, 1, 6);
  for (int f = 0; f < 6; ++f) {
    // x at frame f (1-based) = v (f-1)/fps + f scale, by hand:
    const double slow = 0.25 * f / 4 + (f + 1) * 0.5, fast = 3.0 * f / 4 + (f + 1) * 2.0;
    EXPECT_EQ(grouped[f]["both.result"], flat[f]["both.result"]) << "frame " << f + 1;
    EXPECT_DOUBLE_EQ(grouped[f]["both.result"].get<double>(), slow * fast);
    EXPECT_EQ(grouped[f]["slow.x"], flat[f]["slow_sum.result"]);  // an instance output, by its name
  }
}

TEST(Groups, AGroupedImageIsByteIdenticalToTheFlatOne) {
  testing::Engine engine;
  const json group = {{"inputs", {{"image", {{"type", "Image"}, {"to", {"p.image"}}}},
                                  {"levels", {{"type", "Int"}, {"default", 3}, {"min", 2}, {"max", 8}, {"to", {"p.levels"}}}}}},
                      {"outputs", {{"image", {{"from", "p.image"}}}}},
                      {"nodes", {{"p", {{"type", "Posterize"}}}}}};
  const json grouped = {{"loom", 2}, {"groups", {{"Poster", group}}},
                        {"nodes", {{"board", {{"type", "Checkerboard"}, {"inputs", {{"size", {64, 48}}, {"cells", 5}}}}},
                                   {"look", {{"type", "Poster"}, {"inputs", {{"image", link("board.image")}}}}}}}};
  const json flat = {{"loom", 1},
                     {"nodes", {{"board", {{"type", "Checkerboard"}, {"inputs", {{"size", {64, 48}}, {"cells", 5}}}}},
                                {"look_p", {{"type", "Posterize"}, {"inputs", {{"image", link("board.image")}, {"levels", 3}}}}}}}};
  const Image a = engine.output<Image>(grouped, "look.image");
  const Image b = engine.output<Image>(flat, "look_p.image");
  ASSERT_EQ(a.pixels.total() * a.pixels.elemSize(), b.pixels.total() * b.pixels.elemSize());
  EXPECT_EQ(0, std::memcmp(a.pixels.data, b.pixels.data, a.pixels.total() * a.pixels.elemSize()));
}

bool same_bytes(const Image& a, const Image& b) {
  return a.pixels.total() * a.pixels.elemSize() == b.pixels.total() * b.pixels.elemSize() &&
         std::memcmp(a.pixels.data, b.pixels.data, a.pixels.total() * a.pixels.elemSize()) == 0;
}

// Issue 42, item 1: the library's `studio` framed its mesh anew at every frame;
// its `camera` input keeps the view where the Camera node puts it. The group
// with a camera renders what the same chain wired by hand renders.
TEST(Groups, TheStudioLibraryGroupLooksThroughTheCameraGiven) {
  testing::Engine engine;
  const json mesh = {{"type", "UVSphere"}, {"inputs", {{"rings", 8}, {"segments", 12}}}};
  const json camera = {{"type", "Camera"}, {"inputs", {{"eye", {1.5, 1.0, 3.0}}, {"fov_degrees", 30}}}};
  json grouped = {{"loom", 2},
                  {"nodes", {{"ball", mesh}, {"paint", {{"type", "Material"}}}, {"cam", camera},
                             {"look", {{"type", "studio"},
                                       {"inputs", {{"mesh", link("ball.mesh")}, {"material", link("paint.material")},
                                                   {"camera", link("cam.scene")}, {"width", 40}, {"height", 30}}}}}}}};
  const json flat = {
      {"loom", 1},
      {"nodes",
       {{"ball", mesh}, {"paint", {{"type", "Material"}}}, {"cam", camera},
        {"light", {{"type", "Light"}, {"inputs", {{"kind", "directional"}, {"direction", {-0.3, -0.5, -1}},
                                                  {"intensity", 2.5}, {"casts_shadow", false}}}}},
        {"sky", {{"type", "Environment"}, {"inputs", {{"color", {0.3, 0.3, 0.3}}}}}},
        {"object", {{"type", "Object"}, {"inputs", {{"mesh", link("ball.mesh")}, {"material", link("paint.material")}}}}},
        {"scene", {{"type", "MergeScenes"}, {"inputs", {{"a", link("object.scene")}, {"b", link("light.scene")},
                                                       {"c", link("sky.scene")}, {"d", link("cam.scene")}}}}},
        {"render", {{"type", "Render"}, {"inputs", {{"scene", link("scene.scene")}, {"shadows", "off"},
                                                    {"extra_images", false}, {"width", 40}, {"height", 30}}}}}}}};
  const Image through_camera = engine.output<Image>(grouped, "look.image");
  EXPECT_TRUE(same_bytes(through_camera, engine.output<Image>(flat, "render.image")));
  grouped["nodes"]["look"]["inputs"].erase("camera");
  EXPECT_FALSE(same_bytes(through_camera, engine.output<Image>(grouped, "look.image")));  // the automatic framing
}

// Sleep passes its value on after `ms`: the group's inner node runs once for
// two instances fed equal values, twice for different values.
json two_instances(double a, double b) {
  const json group = {{"inputs", {{"value", {{"type", "Float"}, {"to", {"nap.value"}}}}}},
                      {"outputs", {{"value", {{"from", "nap.value"}}}}},
                      {"nodes", {{"nap", {{"type", "Sleep"}, {"inputs", {{"ms", 5}}}}}}}};
  return {{"loom", 2}, {"groups", {{"Nap", group}}},
          {"nodes", {{"one", {{"type", "Nap"}, {"inputs", {{"value", a}}}}},
                     {"two", {{"type", "Nap"}, {"inputs", {{"value", b}}}}},
                     {"sum", {{"type", "Math"}, {"inputs", {{"a", link("one.value")}, {"b", link("two.value")}}}}}}}};
}

// Ten: x -> x + 10 by 10 chained Math nodes; Hundred: 10 chained Tens.
json ten_of(const std::string& inner, const std::string& in, const std::string& out) {
  json g = {{"inputs", {{"x", {{"type", "Float"}, {"default", 0}, {"to", {"s0." + in}}}}}},
            {"outputs", {{"x", {{"from", "s9." + out}}}}}};
  for (int i = 9; i >= 0; --i) {
    json& n = g["nodes"]["s" + std::to_string(i)];
    n["type"] = inner;
    if (i > 0) n["inputs"][in] = link("s" + std::to_string(i - 1) + "." + out);
    if (inner == "Math") n["inputs"]["b"] = 1;
  }
  return g;
}

TEST(Groups, NestedGroupsExpandToTheirInnerChain) {
  testing::Engine engine;
  const json doc = {{"loom", 2},
                    {"groups", {{"Ten", ten_of("Math", "a", "result")}, {"Hundred", ten_of("Ten", "x", "x")}}},
                    {"nodes", {{"h", {{"type", "Hundred"}, {"inputs", {{"x", 0.5}}}}}}}};
  const Graph g = engine.load(doc, "n.json");
  EXPECT_EQ(g.nodes.size(), 100u);
  EXPECT_TRUE(g.instances.count("h.s3"));
  EXPECT_EQ(engine.output<double>(doc, "h.x"), 100.5);
  EXPECT_EQ(engine.output<double>(doc, "h.s3.s4.result"), 35.5);  // 3 tens and 5 ones
  EXPECT_EQ(engine.output<double>(doc, "h.s3.x"), 40.5);
}

TEST(Groups, TwoInstancesWithEqualInputsShareTheirInnerResults) {
  testing::Engine engine({LOOM_TEST_PLUGIN_DIR});
  testing::Run same = engine.run(two_instances(2, 2), {"sum.result"});
  ASSERT_TRUE(same.ok()) << same.errors();
  EXPECT_EQ(same.output<double>("sum.result"), 4.0);
  const auto& nodes = same.result().nodes;
  EXPECT_EQ(nodes.at("one.nap").runs + nodes.at("two.nap").runs, 1);
  testing::Run different = engine.run(two_instances(2, 5), {"sum.result"});
  EXPECT_EQ(different.output<double>("sum.result"), 7.0);
  // one.nap (value 2) was computed by the first run; two.nap (5) is new.
  EXPECT_EQ(different.status("one.nap"), NodeStatus::cached);
  EXPECT_EQ(different.result().nodes.at("two.nap").runs, 1);
}

TEST(Groups, SelfReferenceThroughFilesIsRefusedWithTheChainNamed) {
  Folder f;
  const json a = {{"loom", 2}, {"outputs", {{"x", {{"from", "b.x"}}}}}, {"nodes", {{"b", {{"type", "b.json"}}}}}};
  const json b = {{"loom", 2}, {"outputs", {{"x", {{"from", "a.x"}}}}}, {"nodes", {{"a", {{"type", "lib/../a.json"}}}}}};
  f.write("a.json", a);
  f.write("b.json", b);
  f.write("lib/keep.json", json::object());
  try {
    (void)load_graph_file(f.dir / "a.json");
    FAIL() << "no error";
  } catch (const GraphError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("uses itself"), std::string::npos) << what;
    EXPECT_NE(what.find("b.json → "), std::string::npos) << what;
    EXPECT_NE(what.find("/nodes/a/type"), std::string::npos) << what;
  }
}

TEST(Groups, ErrorsPointIntoTheGroupFile) {
  testing::Engine engine;
  Folder f;
  const json lib = {{"loom", 2},
                    {"inputs", {{"x", {{"type", "Float"}, {"min", 0}, {"to", {"m.a"}}}},
                                {"img", {{"type", "Image"}, {"to", {"m.b"}}}}}},
                    {"outputs", {{"y", {{"from", "m.result"}}}}},
                    {"nodes", {{"m", {{"type", "Math"}, {"inputs", {{"op", "modulo"}}}}}}}};
  f.write("lib/calc.json", lib);
  json top = {{"loom", 2},
              {"nodes", {{"board", {{"type", "Checkerboard"}}},
                         {"c", {{"type", "lib/calc.json"}, {"inputs", {{"x", -1}, {"img", link("board.image")}}}}}}}};
  const fs::path file = f.write("top.json", top);
  try {
    (void)engine.load(top, file);
    FAIL() << "no error";
  } catch (const GraphError& e) {
    const std::string what = e.what();
    // An inner node's value, in the group file:
    EXPECT_NE(what.find("lib/calc.json: /nodes/m/inputs/op: \"modulo\" is not one of the choices"), std::string::npos) << what;
    // A mistyped binding, at its declaration:
    EXPECT_NE(what.find("lib/calc.json: /inputs/img/type: interface input \"img\" is Image but it feeds c.m.b, which expects Float"),
              std::string::npos) << what;
    // What the instance gives, in the top file, checked by the interface's declaration:
    EXPECT_NE(what.find("top.json: /nodes/c/inputs/x: "), std::string::npos) << what;
  }
  // An inline group's node: its pointer under /groups.
  const json inline_doc = {{"loom", 2},
                           {"groups", {{"G", {{"nodes", {{"m", {{"type", "Math"}, {"inputs", {{"op", "modulo"}}}}}}}}}}},
                           {"nodes", {{"i", {{"type", "G"}}}}}};
  try {
    (void)engine.load(inline_doc, f.dir / "inline.json");
    FAIL() << "no error";
  } catch (const GraphError& e) {
    EXPECT_NE(std::string(e.what()).find("inline.json: /groups/G/nodes/m/inputs/op: \"modulo\""), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("(node \"i.m\")"), std::string::npos) << e.what();
  }
  top["nodes"]["c"]["inputs"]["z"] = 2;  // not an input of the group: refused at load
  try {
    (void)engine.load(top, f.write("top.json", top));
    FAIL() << "no error";
  } catch (const GraphError& e) {
    EXPECT_NE(std::string(e.what()).find("top.json: /nodes/c/inputs/z: unknown input \"z\" of group lib/calc.json (its inputs: img, x)"),
              std::string::npos) << e.what();
  }
}

// LOOM_GRAPH_PATH before the shipped library; a group named like a node type
// is refused.
TEST(Groups, BareNamesAreFoundOnTheGraphPathThenInTheShippedLibrary) {
  testing::Engine engine;
  Folder f;
  const json twice = {{"loom", 2},
                      {"inputs", {{"x", {{"type", "Float"}, {"default", 0}, {"to", {"m.a", "m.b"}}}}}},
                      {"outputs", {{"y", {{"from", "m.result"}}}}},
                      {"nodes", {{"m", {{"type", "Math"}}}}}};
  f.write("mine/twice.json", twice);
  f.write("clash/Math.json", twice);
  const std::string old = std::getenv("LOOM_GRAPH_PATH") ? std::getenv("LOOM_GRAPH_PATH") : "";
  ::setenv("LOOM_GRAPH_PATH", (f.dir / "nowhere").string().append(":").append((f.dir / "mine").string()).c_str(), 1);
  const json doc = {{"loom", 2}, {"nodes", {{"t", {{"type", "twice"}, {"inputs", {{"x", 21}}}}}}}};
  EXPECT_EQ(engine.output<double>(doc, "t.y"), 42.0);
  EXPECT_FALSE(find_group_file("studio", f.dir / "g.json").empty());  // the shipped library, last
  ::setenv("LOOM_GRAPH_PATH", (f.dir / "clash").string().c_str(), 1);
  try {
    (void)engine.load(json{{"loom", 2}, {"nodes", {{"m", {{"type", "Math"}}}}}});
    FAIL() << "no error";
  } catch (const GraphError& e) {
    EXPECT_NE(std::string(e.what()).find("/nodes/m/type: \"Math\" names both a group and a node type (of plugin util)"),
              std::string::npos) << e.what();
  }
  ::setenv("LOOM_GRAPH_PATH", old.c_str(), 1);
}

// The interface's range holds for linked values too: checked when the value
// arrives at the inner input, with the group input named.
TEST(Groups, ALinkedValueOutsideTheInterfaceRangeFailsTheInnerNode) {
  testing::Engine engine;
  const json group = {{"inputs", {{"x", {{"type", "Float"}, {"min", 0}, {"max", 10}, {"to", {"m.a"}}}}}},
                      {"outputs", {{"y", {{"from", "m.result"}}}}},
                      {"nodes", {{"m", {{"type", "Math"}, {"inputs", {{"b", 1}}}}}}}};
  auto doc = [&](double v) {
    return json{{"loom", 2}, {"groups", {{"Small", group}}},
                {"nodes", {{"v", {{"type", "Math"}, {"inputs", {{"a", v}}}}},
                           {"g", {{"type", "Small"}, {"inputs", {{"x", link("v.result")}}}}}}}};
  };
  EXPECT_EQ(engine.output<double>(doc(4), "g.y"), 5.0);
  testing::Run run = engine.run(doc(20), {"g.y"});
  EXPECT_EQ(run.status("g.m"), NodeStatus::failed);
  EXPECT_NE(run.error("g.m").find("group input \"x\" of g: value 20.0 is out of range: expected between 0 and 10"), std::string::npos) << run.error("g.m");
}

TEST(Groups, SetAndTargetReachInnerNodesByPath) {
  testing::Engine engine({LOOM_TEST_PLUGIN_DIR});
  Graph g = engine.load(two_instances(2, 3), "t.json");
  set_input(g, "one.value=10");        // the interface input
  set_input(g, "two.nap.value=20");    // the inner node itself
  Session session(engine.registry());
  EvalOptions o;
  o.targets = {parse_target("sum.result"), parse_target("one.value"), parse_target("two.nap")};
  const EvalResult r = session.evaluate(g, o);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.outputs.at("sum.result").at(0).as<double>(), 30.0);
  EXPECT_EQ(r.outputs.at("one.value").at(0).as<double>(), 10.0);
  EXPECT_EQ(r.outputs.at("two.nap.value").at(0).as<double>(), 20.0);  // an inner node, every output
  EXPECT_THROW(set_input(g, "one.nothing=1"), GraphError);
}

// Body "Step": x -> x * 1.5 + iteration.
json step_group() {
  return {{"inputs", {{"x", {{"type", "Float"}, {"to", {"times.a"}}}},
                      {"iteration", {{"type", "Float"}, {"to", {"plus.b"}}}}}},
          {"outputs", {{"x", {{"from", "plus.result"}}}}},
          {"nodes", {{"times", {{"type", "Math"}, {"inputs", {{"b", 1.5}, {"op", "multiply"}}}}},
                     {"plus", {{"type", "Math"}, {"inputs", {{"a", link("times.result")}}}}}}}};
}

json repeated(const json& count, bool cache = false) {
  json r = {{"type", "Repeat"}, {"body", "Step"}, {"inputs", {{"count", count}, {"x", 2.0}}}};
  if (cache) r["cache_iterations"] = true;
  return {{"loom", 2}, {"groups", {{"Step", step_group()}}}, {"nodes", {{"loop", r}, {"clock", {{"type", "Time"}}}}}};
}

TEST(Repeat, NIterationsEqualNCopiesWiredByHand) {
  testing::Engine engine;
  for (int n : {1, 2, 7}) {
    json nodes = json::object();
    std::string x = "";
    for (int i = 0; i < n; ++i) {
      const std::string t = "times" + std::to_string(i), p = "plus" + std::to_string(i);
      nodes[t] = {{"type", "Math"}, {"inputs", {{"a", x.empty() ? json(2.0) : link(x)}, {"b", 1.5}, {"op", "multiply"}}}};
      nodes[p] = {{"type", "Math"}, {"inputs", {{"a", link(t + ".result")}, {"b", i}}}};
      x = p + ".result";
    }
    const double by_hand = engine.output<double>(json{{"loom", 1}, {"nodes", nodes}}, x);
    EXPECT_EQ(engine.output<double>(repeated(n), "loop.x"), by_hand) << n;
    EXPECT_EQ(engine.output<double>(repeated(n, true), "loop.x"), by_hand) << n;
  }
  // count from a link: the frame number (Time.frame is 1 without "time").
  EXPECT_EQ(engine.output<double>(repeated(link("clock.frame")), "loop.x"), 3.0);
}

// Issue 38, item 8: with cache_iterations a body runs on the outer session,
// whose per-node scratch was keyed by the bare id: the body's "keep" found the
// top-level "keep"'s value.
TEST(Repeat, ABodyNodeNeverSharesScratchWithATopLevelNodeOfItsId) {
  testing::Engine engine({LOOM_TEST_PLUGIN_DIR});
  const json body = {{"inputs", {{"x", {{"type", "Float"}, {"to", {"keep.value"}}}}}},
                     {"outputs", {{"x", {{"from", "keep.value"}}}}},
                     {"nodes", {{"keep", {{"type", "FirstValue"}}}}}};
  const json doc = {{"loom", 2},
                    {"groups", {{"Keep", body}}},
                    {"nodes",
                     {{"keep", {{"type", "FirstValue"}, {"inputs", {{"value", 1.0}}}}},
                      {"loop", {{"type", "Repeat"}, {"body", "Keep"}, {"cache_iterations", true},
                                {"inputs", {{"count", 1}, {"x", 2.0}}}}}}}};
  const auto run = engine.run(doc, {"keep.value", "loop.x"});
  EXPECT_EQ(run.output<double>("keep.value"), 1.0);
  EXPECT_EQ(run.output<double>("loop.x"), 2.0);
}

// SmoothMesh's own loop of `steps` is the reference for 12 iterations of one step.
TEST(Repeat, TwelveIterationsOfOneSmoothingStepEqualSmoothMeshsOwnTwelveSteps) {
  testing::Engine engine;
  const json once = {{"inputs", {{"mesh", {{"type", "Mesh"}, {"to", {"smooth.mesh"}}}}}},
                     {"outputs", {{"mesh", {{"from", "smooth.mesh"}}}}},
                     {"nodes", {{"smooth", {{"type", "SmoothMesh"}, {"inputs", {{"steps", 1}}}}}}}};
  const json dome = {{"type", "HemisphereMesh"}, {"inputs", {{"rings", 12}, {"segments", 40}, {"noise", 0.06}}}};
  const json repeat = {{"loom", 2}, {"seed", 3}, {"groups", {{"SmoothOnce", once}}},
                       {"nodes", {{"dome", dome},
                                  {"loop", {{"type", "Repeat"}, {"body", "SmoothOnce"},
                                            {"inputs", {{"count", 12}, {"mesh", link("dome.mesh")}}}}}}}};
  const json direct = {{"loom", 1}, {"seed", 3},
                       {"nodes", {{"dome", dome},
                                  {"s", {{"type", "SmoothMesh"}, {"inputs", {{"mesh", link("dome.mesh")}, {"steps", 12}}}}}}}};
  const Mesh a = engine.output<Mesh>(repeat, "loop.mesh"), b = engine.output<Mesh>(direct, "s.mesh");
  const Mesh raw = engine.output<Mesh>(direct, "dome.mesh");
  ASSERT_EQ(a.V.rows(), b.V.rows());
  EXPECT_TRUE(a.V == b.V);  // bit for bit
  EXPECT_FALSE(a.V == raw.V);
}

TEST(Repeat, ZeroIterationsPassTheThreadedInputThrough) {
  testing::Engine engine;
  EXPECT_EQ(engine.output<double>(repeated(0), "loop.x"), 2.0);
  json body = step_group();
  body["outputs"]["other"] = {{"from", "times.result"}};  // no input "other": not threaded
  json doc = repeated(0);
  doc["groups"]["Step"] = body;
  testing::Run run = engine.run(doc, {"loop.other"});
  EXPECT_EQ(run.status("loop"), NodeStatus::failed);
  EXPECT_NE(run.error("loop").find("not threaded"), std::string::npos) << run.error("loop");
}

TEST(Repeat, IterationsAreNotCachedUnlessAsked) {
  testing::Engine engine;
  Session session(engine.registry());
  EvalOptions o;
  o.targets = {parse_target("loop.x")};
  session.evaluate(engine.load(repeated(5), "r.json"), o);
  const std::size_t plain = session.cache_entries();
  session.clear_cache();
  session.evaluate(engine.load(repeated(5, true), "r.json"), o);
  EXPECT_EQ(plain, 1u);  // the Repeat node's own result
  EXPECT_GE(session.cache_entries(), 1u + 5u * 2u);  // and every inner node of every iteration
}

TEST(Repeat, CancelInsideTheBodyEndsTheRun) {
  testing::Engine engine({LOOM_TEST_PLUGIN_DIR});
  const json body = {{"inputs", {{"value", {{"type", "Float"}, {"to", {"nap.value"}}}}}},
                     {"outputs", {{"value", {{"from", "nap.value"}}}}},
                     {"nodes", {{"nap", {{"type", "Sleep"}, {"inputs", {{"ms", 20}}}}}}}};
  const json doc = {{"loom", 2}, {"groups", {{"Nap", body}}},
                    {"nodes", {{"loop", {{"type", "Repeat"}, {"body", "Nap"}, {"inputs", {{"count", 100000}, {"value", 1.0}}}}}}}};
  const Graph g = engine.load(doc, "c.json");
  Session session(engine.registry());
  std::atomic<bool> cancel{false};
  EvalOptions o;
  o.targets = {parse_target("loop.value")};
  o.cancel = &cancel;
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    cancel = true;
  });
  const auto start = std::chrono::steady_clock::now();
  const EvalResult r = session.evaluate(g, o);
  stopper.join();
  EXPECT_TRUE(r.cancelled);
  EXPECT_NE(r.nodes.at("loop").status, NodeStatus::ran);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 30.0);
  EXPECT_EQ(session.cache_entries(), 0u);
}

TEST(GraphFormat, EveryExampleGraphLoadsTheSameAsVersion1AndVersion2) {
  int graphs = 0;
  for (const auto& e : fs::directory_iterator(fs::path(LOOM_SOURCE_DIR) / "graphs")) {
    if (e.path().extension() != ".json") continue;
    std::ifstream in(e.path());
    json doc = json::parse(in);
    if (doc["loom"] != 1) continue;  // the examples of groups are version 2 already
    const Graph v1 = parse_graph(doc, e.path());
    doc["loom"] = 2;
    const Graph v2 = parse_graph(doc, e.path());
    EXPECT_EQ(graph_to_json(v1), graph_to_json(v2)) << e.path();
    EXPECT_TRUE(v2.instances.empty());
    ++graphs;
  }
  EXPECT_GT(graphs, 30);
}

}  // namespace
}  // namespace loom
