#include "loom_test.hpp"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <random>

#include <sys/wait.h>

namespace loom::test {

namespace fs = std::filesystem;

Engine::Engine()
    : loader(registry, {fs::path(LOOM_PLUGIN_DIR), fs::path(LOOM_TEST_PLUGIN_DIR)}), session(registry) {}

Graph Engine::graph(const json& document, const fs::path& file) {
  Graph g = parse_graph(document, fs::absolute(file));
  loader.load_for(node_types_used(g));
  validate_graph(g, registry, loader.searched_description(), loader.known_node_types());
  return g;
}

EvalResult Engine::run(const Graph& g, std::vector<std::string> targets, int threads,
                       const fs::path& out) {
  EvalOptions options;
  for (const auto& t : targets) options.targets.push_back(parse_target(t));
  options.threads = threads;
  options.output_dir = out.empty() ? temp_dir() : out;
  return session.evaluate(g, options);
}

Value Engine::output(const json& document, const std::string& node_output) {
  EvalResult r = run(graph(document), {node_output});
  const Target t = parse_target(node_output);
  const NodeReport& report = r.nodes.at(t.node);
  if (report.status != NodeStatus::ran && report.status != NodeStatus::cached)
    throw Error("node " + t.node + " " + to_string(report.status) + ": " + report.error);
  return r.outputs.at(node_output).at(0);
}

fs::path data_file(const std::string& relative) {
  fs::path p = fs::path(LOOM_DATA_DIR) / relative;
  return fs::exists(p) ? p : fs::path();
}

fs::path temp_dir() {
  static std::mt19937_64 rng(std::random_device{}());
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "loom";
  fs::path dir = fs::temp_directory_path() / ("loom-test-" + name + "-" + std::to_string(rng() % 1000000));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string fresh_cache_env(const std::string& arguments) {
  if (arguments.find("--cache") != std::string::npos) return "";
  return "XDG_CACHE_HOME=" + (temp_dir() / "xdg-cache").string() + " ";
}

int run_loom(const std::string& arguments, std::string* output) { return run_loom_env("", arguments, output); }

int run_loom_env(const std::string& environment, const std::string& arguments, std::string* output) {
  return run_shell("env " + environment + " " + fresh_cache_env(arguments) + LOOM_RUNNER + " " + arguments, output);
}

int run_shell(const std::string& script, std::string* output) {
  std::string cmd = "( " + script + " ) 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return -1;
  std::string text;
  std::array<char, 4096> buffer{};
  std::size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) text.append(buffer.data(), n);
  int status = ::pclose(pipe);
  if (output) *output = text;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace loom::test
