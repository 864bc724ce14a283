// What the runner tests (runner_tests) share: graphs written as JSON, the
// runner with the test plugins, files read back.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "loom/value.hpp"
#include "run_loom.hpp"
#include "test_files.hpp"

namespace loom::test {

inline json from(const std::string& link) { return {{"from", link}}; }

inline std::filesystem::path write_graph(const std::filesystem::path& dir, const json& doc,
                                         const std::string& name = "g.json") {
  std::ofstream(dir / name) << doc.dump(2);
  return dir / name;
}

inline std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline json read_json(const std::filesystem::path& p) { return json::parse(read_text(p)); }

// `loom ARGS` with the test plugins (testnodes) on the plugin path.
inline int loom_with_test_plugins(const std::string& args, std::string* out) {
  return run_loom_env("LOOM_PLUGIN_PATH=" LOOM_TEST_PLUGIN_DIR, args, out);
}

// FrameNumber -> Sleep(ms) -> WriteText x_{frame}.txt over frames 1..frames:
// a time-dependent node of `ms` a frame that reports progress every millisecond.
inline json sequence_graph(int frames, int ms) {
  return {{"loom", 1},
          {"time", {{"start", 1}, {"end", frames}, {"fps", 24}}},
          {"nodes",
           {{"f", {{"type", "FrameNumber"}}},
            {"slow", {{"type", "Sleep"}, {"inputs", {{"value", from("f.value")}, {"ms", ms}}}}},
            {"w", {{"type", "WriteText"}, {"inputs", {{"value", from("slow.value")}, {"path", "x_{frame}.txt"}}}}}}}};
}

}  // namespace loom::test
