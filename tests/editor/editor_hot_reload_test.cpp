// Plugin hot reload (issue 28, item 14): a plugin scaffolded by `loom
// new-plugin` (hot_reload.sh builds it) is edited and rebuilt with its own
// CMake while the editor runs. The editor must load the new build, re-run
// the plugin's node and what it feeds, keep the cached results of every
// other node, and leave the document alone. The reference for the new
// result is the old one: the edit multiplies the exposure's gain by 2, so
// every pixel doubles (the checkerboard's values are below 0.5 times the
// old gain's inverse, so nothing clips).
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>

#include "loom/image.hpp"
#include "ui_harness.hpp"

namespace loom::editor::test {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

TEST(EditorHotReload, RebuiltPluginIsReloadedAndOnlyWhatUsedItRecomputes) {
  const char* source = std::getenv("LOOM_HOT_RELOAD_PLUGIN");
  if (!source) GTEST_SKIP() << "run through tests/editor/hot_reload.sh (it scaffolds and builds the plugin)";
  const fs::path plugin(source);
  EditorOptions options = Harness::options();
  options.plugin_path.push_back(plugin / "build" / "lib" / "loom" / "plugins");
  Window window("hot reload", 1600, 900, false);
  EditorApp app(options);
  ScriptedInput input;
  auto frame = [&] {
    window.begin_frame(&input);
    app.draw(window);
    window.end_frame();
  };
  auto settle = [&](double timeout) {
    const auto start = Clock::now();
    while (seconds(start, Clock::now()) < timeout) {
      frame();
      if (app.evaluation_current()) return true;
    }
    return false;
  };

  // board -> exposure (the scaffolded node) -> warp; and an independent board.
  const json graph = {{"loom", 1},
                      {"nodes",
                       {{"board", {{"type", "Checkerboard"}, {"inputs", {{"size", {64, 64}}, {"cells", 4}}}}},
                        {"exposure", {{"type", "HotfxExposure"}, {"inputs", {{"image", {{"from", "board.image"}}}, {"stops", -2}}}}},
                        {"warp", {{"type", "ImageWarp"}, {"inputs", {{"image", {{"from", "exposure.image"}}}}}}},
                        {"other", {{"type", "Checkerboard"}, {"inputs", {{"size", {32, 32}}}}}}}}};
  const fs::path file = loom::test::temp_dir() / "hot.json";
  std::ofstream(file) << graph.dump(1);
  app.open(file);
  ASSERT_TRUE(settle(120)) << app.message();
  auto eval = app.state().eval;
  ASSERT_TRUE(eval->result.ok()) << app.message();
  const Image before = eval->output("exposure", "image").as<Image>();
  const json document = app.document().document();

  // The author's edit: twice the gain. Then their build, while the editor runs.
  const fs::path exposure = plugin / "exposure.cpp";
  std::stringstream text;
  text << std::ifstream(exposure).rdbuf();
  std::string code = text.str();
  const std::string gain = "std::exp2(in.get<double>(\"stops\"))";
  const auto at = code.find(gain);
  ASSERT_NE(at, std::string::npos) << "the scaffold's exposure.cpp changed: update this test";
  code.replace(at, gain.size(), "2.0 * " + gain);
  std::ofstream(exposure) << code;
  std::atomic<bool> built{false};
  std::atomic<int> status{-1};
  Clock::time_point build_done{};
  std::thread builder([&] {
    status = std::system(("cmake --build " + (plugin / "build").string() + " --target loom_hotfx > " +
                          (plugin / "rebuild.log").string() + " 2>&1")
                             .c_str());
    build_done = Clock::now();
    built = true;
  });
  const auto build_start = Clock::now();
  while (app.last_reload().count == 0 && seconds(build_start, Clock::now()) < 600) frame();
  builder.join();
  ASSERT_EQ(status, 0) << "the plugin did not rebuild: see " << (plugin / "rebuild.log");
  ASSERT_EQ(app.last_reload().count, 1) << app.message();
  EXPECT_EQ(app.last_reload().plugins, std::vector<std::string>{"hotfx"}) << app.message();
  ASSERT_TRUE(settle(120));
  const auto shown = Clock::now();
  eval = app.state().eval;

  // The new build ran; what it feeds ran; the rest came from the cache.
  EXPECT_EQ(eval->result.nodes.at("exposure").status, NodeStatus::ran);
  EXPECT_EQ(eval->result.nodes.at("warp").status, NodeStatus::ran);
  EXPECT_EQ(eval->result.nodes.at("board").status, NodeStatus::cached);
  EXPECT_EQ(eval->result.nodes.at("other").status, NodeStatus::cached);
  const Image after = eval->output("exposure", "image").as<Image>();
  ASSERT_EQ(after.pixels.size(), before.pixels.size());
  EXPECT_LT(cv::norm(after.pixels, before.pixels * 2.0, cv::NORM_INF), 1e-6);
  EXPECT_GT(cv::norm(before.pixels, cv::NORM_INF), 0.05);
  // The document is untouched: same JSON, nothing to save.
  EXPECT_EQ(app.document().document(), document);
  EXPECT_FALSE(app.document().dirty());

  const HotReload& r = app.last_reload();
  std::printf("hot reload: library settled %.2f s after the build finished (300 ms settle + polling), loaded in "
              "%.1f ms, re-evaluated result shown %.2f s after the build finished (load %s)\n",
              seconds(build_done, r.detected), r.load_ms, seconds(build_done, shown),
              [] {
                std::ifstream l("/proc/loadavg");
                std::string s;
                l >> s;
                return s;
              }().c_str());
}

}  // namespace
}  // namespace loom::editor::test
