#include "loom/testing.hpp"

#include <cstdlib>
#include <string>

#include <dlfcn.h>

#include "loom/search_path.hpp"

namespace loom::testing {

namespace fs = std::filesystem;

GraphBuilder::NodeRef& GraphBuilder::NodeRef::set(const std::string& input, const json& literal) {
  (*node_)["inputs"][input] = literal;
  return *this;
}

GraphBuilder::NodeRef& GraphBuilder::NodeRef::link(const std::string& input, const std::string& from) {
  (*node_)["inputs"][input] = {{"from", from}};
  return *this;
}

GraphBuilder::NodeRef GraphBuilder::node(const std::string& id, const std::string& type) {
  json& n = document_["nodes"][id];
  n = {{"type", type}, {"inputs", json::object()}};
  return NodeRef(n);
}

GraphBuilder& GraphBuilder::seed(std::uint64_t seed) {
  document_["seed"] = seed;
  return *this;
}

NodeStatus Run::status(const std::string& node) const {
  auto it = result_.nodes.find(node);
  if (it == result_.nodes.end()) throw Error("no node \"" + node + "\" in the graph that ran");
  return it->second.status;
}

const std::string& Run::error(const std::string& node) const {
  status(node);
  return result_.nodes.at(node).error;
}

const std::vector<std::string>& Run::warnings(const std::string& node) const {
  status(node);
  return result_.nodes.at(node).warnings;
}

std::string Run::errors() const {
  std::string text;
  for (const auto& [id, r] : result_.nodes)
    if (r.status == NodeStatus::failed || r.status == NodeStatus::skipped)
      text += id + " " + to_string(r.status) + ": " + r.error + "\n";
  return text;
}

const Value& Run::stored(const std::string& target) const {
  auto it = result_.outputs.find(target);
  if (it == result_.outputs.end()) {
    const Target t = parse_target(target);
    auto node = result_.nodes.find(t.node);
    if (node != result_.nodes.end() && node->second.status != NodeStatus::ran &&
        node->second.status != NodeStatus::cached)
      throw Error("node \"" + t.node + "\" " + to_string(node->second.status) +
                  (node->second.error.empty() ? "" : ": " + node->second.error));
    throw Error("\"" + target + "\" was not a target of this run (pass it to Engine::run)");
  }
  if (it->second.size() != 1)
    throw Error("\"" + target + "\" has " + std::to_string(it->second.size()) +
                " outputs: name one as ID.OUTPUT");
  return it->second.front();
}

Value Run::value(const std::string& target) const { return stored(target); }

fs::path installed_plugin_dir() {
  Dl_info info{};
  if (::dladdr(reinterpret_cast<const void*>(&installed_plugin_dir), &info) == 0 || !info.dli_fname)
    return {};
  return (fs::path(info.dli_fname).parent_path() / "loom" / "plugins").lexically_normal();
}

namespace {

std::vector<fs::path> search_path(const std::vector<fs::path>& plugin_dirs) {
  std::vector<fs::path> path{installed_plugin_dir()};
  for (const auto& d : plugin_dirs)
    if (!d.empty()) path.push_back(d);
  for (fs::path& dir : search_path_from_env("LOOM_PLUGIN_PATH")) path.push_back(std::move(dir));
  return path;
}

fs::path fresh_temp_dir() {
  std::string pattern = (fs::temp_directory_path() / "loom-testing-XXXXXX").string();
  if (!::mkdtemp(pattern.data())) throw Error("cannot create a temporary folder in " +
                                              fs::temp_directory_path().string());
  return pattern;
}

}  // namespace

struct Engine::State {
  Registry registry;
  PluginLoader loader;
  Session session;
  fs::path temp;  // the default output folder, made on first use, removed with the Engine
  explicit State(std::vector<fs::path> path) : loader(registry, std::move(path)), session(registry) {}
  ~State() {
    std::error_code ec;
    if (!temp.empty()) fs::remove_all(temp, ec);
  }
};

Engine::Engine(std::vector<fs::path> plugin_dirs)
    : state_(std::make_unique<State>(search_path(plugin_dirs))) {}

Engine::~Engine() = default;

Graph Engine::load(const json& document, const fs::path& file) {
  Graph g = parse_graph(document, fs::absolute(file));
  state_->loader.load_for(node_types_used(g));
  validate_graph(g, state_->registry, state_->loader.searched_description(), state_->loader.known_node_types());
  return g;
}

Run Engine::run(const json& document, const std::vector<std::string>& targets, const fs::path& out) {
  return run(load(document), targets, out);
}

Run Engine::run(const Graph& g, const std::vector<std::string>& targets, const fs::path& out) {
  EvalOptions options;
  for (const auto& t : targets) options.targets.push_back(parse_target(t));
  if (out.empty() && state_->temp.empty()) state_->temp = fresh_temp_dir();
  options.output_dir = out.empty() ? state_->temp : fs::absolute(out);
  return Run(state_->session.evaluate(g, options));
}

Run Engine::run(const GraphBuilder& graph, const std::vector<std::string>& targets, const fs::path& out) {
  return run(graph.document(), targets, out);
}

Value Engine::value(const json& document, const std::string& target) { return run(document, {target}).value(target); }

fs::path Engine::output_dir() {
  if (state_->temp.empty()) state_->temp = fresh_temp_dir();
  return state_->temp;
}

void Engine::load_plugins(const std::vector<std::string>& node_types) { state_->loader.load_for(node_types); }
void Engine::load_all_plugins() { state_->loader.load_all(); }
Session& Engine::session() { return state_->session; }

const std::vector<fs::path>& Engine::plugin_path() const { return state_->loader.search_path(); }
std::vector<std::string> Engine::loaded_plugins() const { return state_->loader.loaded_names(); }
const Registry& Engine::registry() const { return state_->registry; }
Registry& Engine::registry() { return state_->registry; }

}  // namespace loom::testing
