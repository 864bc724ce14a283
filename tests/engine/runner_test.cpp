// The `loom` command as a user runs it: exit codes, profiles, lazy plugin
// loading, ABI refusal, atomic writes, interruption.
#include <fstream>
#include <set>

#include <gtest/gtest.h>

#include "loom/evaluator.hpp"
#include "loom/plugin_loader.hpp"
#include "run_loom.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

namespace fs = std::filesystem;

fs::path write_graph(const fs::path& dir, const json& doc, const std::string& name = "g.json") {
  std::ofstream(dir / name) << doc.dump(2);
  return dir / name;
}

json graph(json nodes) { return {{"loom", 1}, {"nodes", std::move(nodes)}}; }
json from(const std::string& link) { return {{"from", link}}; }
const std::string kTestPlugins = "LOOM_PLUGIN_PATH=" LOOM_TEST_PLUGIN_DIR " ";

json read_json(const fs::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}

int loom_with_test_plugins(const std::string& args, std::string* out = nullptr) {
  // run_loom prefixes the binary; the environment goes in front through env(1).
  std::string cmd = "env " + kTestPlugins + test::fresh_cache_env(args) + LOOM_RUNNER + " " + args + " 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  std::string text;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) text.append(buf, n);
  int status = ::pclose(pipe);
  if (out) *out = text;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(Runner, ExitCodeZeroAndAProfileThatLoadsOnlyWhatTheGraphUses) {
  auto dir = test::temp_dir();
  auto g = write_graph(dir, graph({{"a", {{"type", "FloatConstant"}, {"inputs", {{"value", 2}}}}},
                                   {"p", {{"type", "Print"}, {"inputs", {{"value", from("a.value")}}}}},
                                   {"unused", {{"type", "Math"}}}}));
  std::string out;
  ASSERT_EQ(test::run_loom("run " + g.string() + " --profile " + (dir / "profile.json").string(), &out), 0) << out;
  json p = read_json(dir / "profile.json");
  EXPECT_EQ(p["plugins_loaded"], json::array({"util"}));  // not io, generate (OpenCV, assimp)
  EXPECT_EQ(p["nodes"]["p"]["status"], "ran");
  EXPECT_EQ(p["nodes"]["unused"]["status"], "pruned");
  EXPECT_EQ(p["nodes"]["p"]["type"], "Print");
  EXPECT_TRUE(p["total_seconds"].is_number());
  EXPECT_NE(out.find("[p] 2"), std::string::npos) << out;
}

// Issue 42, item 2: a target kept at several frames is the list of its
// values, one per frame (it printed only the last frame's).
TEST(Runner, ATargetOverFramesIsTheListOfItsValues) {
  auto dir = test::temp_dir();
  json doc = graph({{"time", {{"type", "Time"}}}});
  doc["time"] = {{"start", 1}, {"end", 6}, {"fps", 24}};
  auto g = write_graph(dir, doc);
  std::string out;
  ASSERT_EQ(test::run_loom("run " + g.string() + " --target time.frame --frames 2-4 --json -q --no-cache", &out), 0)
      << out;
  const auto start = out.find('{');
  ASSERT_NE(start, std::string::npos) << out;
  EXPECT_EQ(json::parse(out.substr(start))["time.frame"], json::array({2, 3, 4})) << out;
  ASSERT_EQ(test::run_loom("run " + g.string() + " --target time.frame --frames 3 --json -q --no-cache", &out), 0);
  EXPECT_EQ(json::parse(out.substr(out.find('{')))["time.frame"], 3) << out;  // one frame: the value itself
}

TEST(Runner, ExitCodeOneWhenANodeFailsAndOtherOutputsAreStillWritten) {
  auto dir = test::temp_dir();
  auto g = write_graph(dir, graph({{"bad", {{"type", "Fail"}}},
                                   {"w1", {{"type", "WriteText"}, {"inputs", {{"value", from("bad.value")}, {"path", "bad.txt"}}}}},
                                   {"w2", {{"type", "WriteText"}, {"inputs", {{"value", 3}, {"path", "good.txt"}}}}}}));
  std::string out;
  EXPECT_EQ(loom_with_test_plugins("run " + g.string() + " --out " + (dir / "out").string(), &out), 1) << out;
  EXPECT_TRUE(fs::exists(dir / "out" / "good.txt"));
  EXPECT_FALSE(fs::exists(dir / "out" / "bad.txt"));
  EXPECT_NE(out.find("node \"bad\" (Fail) failed: failing on purpose"), std::string::npos) << out;
}

TEST(Runner, ExitCodeTwoForAnInvalidGraphOrUsage) {
  auto dir = test::temp_dir();
  auto g = write_graph(dir, graph({{"m", {{"type", "Math"}, {"inputs", {{"op", "nope"}}}}}}));
  std::string out;
  EXPECT_EQ(test::run_loom("run " + g.string(), &out), 2);
  EXPECT_NE(out.find(g.string() + ": /nodes/m/inputs/op:"), std::string::npos) << out;
  EXPECT_EQ(test::run_loom("run", &out), 2);
  EXPECT_EQ(test::run_loom("frobnicate", &out), 2);
  EXPECT_EQ(test::run_loom("run " + (dir / "missing.json").string(), &out), 2);
  EXPECT_EQ(test::run_loom("validate " + g.string(), &out), 2);
}

TEST(Runner, ExitCodeThreeAndANamedRefusalForAPluginOfAnotherAbi) {
  auto dir = test::temp_dir();
  auto g = write_graph(dir, graph({{"x", {{"type", "BadAbiNode"}}}}));
  std::string out;
  // The bad library has no manifest: it is loaded only when asked.
  std::string cmd = "LOOM_LOAD_UNLISTED=1 LOOM_PLUGIN_PATH=" LOOM_BINARY_DIR "/tests/badabi " LOOM_RUNNER " run " +
                    g.string() + " 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) out.append(buf, n);
  int status = ::pclose(pipe);
  EXPECT_EQ(WEXITSTATUS(status), 3) << out;
  EXPECT_NE(out.find("plugin \"badabi\""), std::string::npos) << out;
  EXPECT_NE(out.find("built for Loom plugin ABI 999, but this Loom has ABI " + std::to_string(engine_abi_version())),
            std::string::npos) << out;
  EXPECT_NE(out.find("rebuild the plugin"), std::string::npos) << out;
}

TEST(Runner, UnlistedLibrariesAndRelativePluginFoldersNeedConsent) {
  auto dir = test::temp_dir();
  auto g = write_graph(dir, graph({{"x", {{"type", "BadAbiNode"}}}}));
  std::string out;
  // Without LOOM_LOAD_UNLISTED the manifest-less library is never opened.
  std::string cmd = "LOOM_PLUGIN_PATH=" LOOM_BINARY_DIR "/tests/badabi " LOOM_RUNNER " run " + g.string() + " 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) out.append(buf, n);
  int status = ::pclose(pipe);
  EXPECT_EQ(WEXITSTATUS(status), 2) << out;
  EXPECT_NE(out.find("without a manifest, not loaded"), std::string::npos) << out;
  // A relative entry is ignored with a warning.
  out.clear();
  cmd = "cd " LOOM_BINARY_DIR "/tests/badabi && LOOM_LOAD_UNLISTED=1 LOOM_PLUGIN_PATH=. " LOOM_RUNNER " run " +
        g.string() + " 2>&1";
  pipe = ::popen(cmd.c_str(), "r");
  while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) out.append(buf, n);
  status = ::pclose(pipe);
  EXPECT_EQ(WEXITSTATUS(status), 2) << out;
  EXPECT_NE(out.find("LOOM_PLUGIN_PATH entry \".\" ignored"), std::string::npos) << out;
}

TEST(Runner, TheLoaderRefusesAnotherAbiInProcessToo) {
  Registry registry;
  PluginLoader loader(registry, {});
  EXPECT_THROW(loader.load_library(LOOM_BINARY_DIR "/tests/badabi/libloom_badabi.so"), PluginLoadError);
  EXPECT_EQ(registry.find("BadAbiNode"), nullptr);
}

TEST(Runner, InterruptCancelsAndExits130WithoutHalfWrittenFiles) {
  auto dir = test::temp_dir();
  auto g = write_graph(dir, graph({{"slow", {{"type", "Sleep"}, {"inputs", {{"ms", 30000}}}}},
                                   {"w", {{"type", "WriteText"}, {"inputs", {{"value", from("slow.value")}, {"path", "x.txt"}}}}}}));
  std::string out;
  int code = loom_with_test_plugins("run " + g.string() + " --out " + (dir / "out").string() + " & pid=$!; sleep 0.5; kill -INT $pid; wait $pid", &out);
  EXPECT_EQ(code, 130) << out;
  EXPECT_FALSE(fs::exists(dir / "out" / "x.txt"));
}

TEST(Runner, SetAndTarget) {
  auto dir = test::temp_dir();
  auto g = write_graph(dir, graph({{"m", {{"type", "Math"}, {"inputs", {{"a", 1}, {"b", 2}}}}}}));
  std::string out;
  EXPECT_EQ(test::run_loom("run " + g.string() + " --target m.result --set m.b=40 -q", &out), 0);
  EXPECT_EQ(out, "m.result = 41\n");
  EXPECT_EQ(test::run_loom("run " + g.string() + " --target nope", &out), 2) << out;
}

TEST(Runner, AtomicWritesLeaveNoTemporaryFiles) {
  auto dir = test::temp_dir();
  auto g = write_graph(dir, graph({{"b", {{"type", "Checkerboard"}, {"inputs", {{"size", {64, 32}}}}}},
                                   {"s", {{"type", "SaveImage"}, {"inputs", {{"image", from("b.image")}, {"path", "sub/b.png"}}}}}}));
  ASSERT_EQ(test::run_loom("run " + g.string() + " -q --out " + (dir / "out").string()), 0);
  int files = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir / "out")) files += e.is_regular_file();
  EXPECT_EQ(files, 1);
  EXPECT_TRUE(fs::exists(dir / "out" / "sub" / "b.png"));
}

TEST(Runner, NodesJsonDescribesEveryType) {
  std::string out;
  ASSERT_EQ(test::run_loom("nodes --json", &out), 0);
  json all = json::parse(out);
  ASSERT_TRUE(all.contains("Math"));
  const json& math = all["Math"];
  EXPECT_EQ(math["plugin"], "util");
  EXPECT_EQ(math["version"], 1);
  EXPECT_FALSE(math["description"].get<std::string>().empty());
  EXPECT_EQ(math["inputs"][0]["name"], "a");
  EXPECT_EQ(math["inputs"][0]["type"], "Float");
  EXPECT_EQ(math["inputs"][2]["choices"].size(), 7u);
  EXPECT_EQ(math["outputs"][0]["name"], "result");
  EXPECT_TRUE(all.contains("SaveImage") && all.contains("LoadMesh") && all.contains("Checkerboard"));
}

TEST(Runner, EveryCommandHasHelp) {
  for (const std::string cmd : {"", "run ", "validate ", "nodes ", "plugins "}) {
    std::string out;
    EXPECT_EQ(test::run_loom(cmd + "--help", &out), 0) << cmd;
    EXPECT_NE(out.find("Usage:"), std::string::npos) << cmd;
  }
}

TEST(Runner, EveryNodeTypeHasAnExampleGraph) {
  std::string out;
  ASSERT_EQ(test::run_loom("nodes --json", &out), 0);
  std::set<std::string> used;
  for (const auto& e : fs::directory_iterator(fs::path(LOOM_SOURCE_DIR) / "graphs"))
    if (e.path().extension() == ".json") {
      const json doc = read_json(e.path());
      for (const auto& [id, node] : doc["nodes"].items()) used.insert(node["type"].get<std::string>());
    }
  const json types = json::parse(out);  // items() of a temporary would dangle
  for (const auto& [type, description] : types.items())
    EXPECT_TRUE(used.count(type)) << type << " (plugin " << description["plugin"].get<std::string>()
                                  << ") has no example graph under graphs/";
}

TEST(Runner, NodeReferenceIsCurrent) {
  std::string out;
  ASSERT_EQ(test::run_loom("nodes --markdown", &out), 0);
  std::ifstream in(fs::path(LOOM_SOURCE_DIR) / "docs" / "nodes.md");
  std::string doc((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_TRUE(doc == out) << "docs/nodes.md is stale: regenerate it with\n"
                             "  build/bin/loom nodes --markdown > docs/nodes.md";
}

}  // namespace
}  // namespace loom
