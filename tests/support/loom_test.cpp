#include "loom_test.hpp"

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

}  // namespace loom::test
