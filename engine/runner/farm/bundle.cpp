#include "farm/bundle.hpp"

#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "loom/atomic_file.hpp"
#include "loom/hash.hpp"

namespace loom::runner {

namespace fs = std::filesystem;

namespace {

json read_document(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  json doc = json::parse(text.str(), nullptr, false);
  if (!in || doc.is_discarded()) throw Error("cannot read " + file.string() + " again to copy it into the job");
  return doc;
}

class Bundler {
 public:
  Bundler(const Registry& registry, const fs::path& graph_dir, const fs::path& job)
      : registry_(registry), graph_dir_(graph_dir), job_(job) {}

  // The copy's path of a group file, relative to the job folder; queued once.
  std::string place_of(const fs::path& file) {
    const std::string key = file.lexically_normal().string();
    auto [it, fresh] = places_.emplace(key, std::string());
    if (fresh) {
      char digest[17];
      std::snprintf(digest, sizeof digest, "%016llx", static_cast<unsigned long long>(Hasher().str(key).digest()));
      it->second = "groups/" + std::string(digest, 8) + "/" + file.filename().string();
      queue_.push_back(file);
    }
    return it->second;
  }

  // Rewrites the group references and input paths of one document, whose
  // copy lies at `self` (relative to the job folder).
  void rewrite(json& doc, const fs::path& file, const std::string& self) {
    std::set<std::string> inline_names;
    if (doc.contains("groups") && doc["groups"].is_object())
      for (const auto& [name, def] : doc["groups"].items()) inline_names.insert(name);
    auto rewrite_nodes = [&](json& nodes) {
      if (!nodes.is_object()) return;
      for (auto& [id, node] : nodes.items()) {
        if (!node.is_object() || !node.contains("type") || !node["type"].is_string()) continue;
        const std::string type = node["type"];
        const char* key = type == "Repeat" ? "body" : "type";
        if (!node.contains(key) || !node[key].is_string()) continue;
        const std::string ref = node[key];
        if (inline_names.count(ref)) continue;
        if (type != "Repeat" && registry_.find(type)) {
          absolute_input_paths(node, *registry_.find(type));
          continue;
        }
        const fs::path found = find_group_file(ref, file);
        if (found.empty()) continue;  // validated: a type of a plugin
        node[key] = fs::path(place_of(found)).lexically_relative(fs::path(self).parent_path()).string();
      }
    };
    if (doc.contains("nodes")) rewrite_nodes(doc["nodes"]);
    if (doc.contains("groups") && doc["groups"].is_object())
      for (auto& [name, def] : doc["groups"].items())
        if (def.is_object() && def.contains("nodes")) rewrite_nodes(def["nodes"]);
  }

  void absolute_input_paths(json& node, const NodeType& type) {
    if (!node.contains("inputs") || !node["inputs"].is_object()) return;
    for (auto& [name, value] : node["inputs"].items()) {
      const InputSpec* spec = type.spec.find_input(name);
      if (!spec || spec->role != InputRole::input_file || !value.is_string()) continue;
      const fs::path p = value.get<std::string>();
      if (!p.empty() && p.is_relative()) value = (graph_dir_ / p).lexically_normal().string();
    }
  }

  void write(const fs::path& graph_file) {
    json top = read_document(graph_file);
    rewrite(top, graph_file, "graph.json");
    write_file_atomic(job_ / "graph.json", top.dump(1) + "\n");
    for (std::size_t k = 0; k < queue_.size(); ++k) {
      const fs::path file = queue_[k];
      const std::string self = places_.at(file.lexically_normal().string());
      json doc = read_document(file);
      rewrite(doc, file, self);
      write_file_atomic(job_ / self, doc.dump(1) + "\n");
    }
  }

 private:
  const Registry& registry_;
  fs::path graph_dir_, job_;
  std::map<std::string, std::string> places_;
  std::vector<fs::path> queue_;
};

}  // namespace

void write_bundle(const GraphView& view, const Registry& registry, const fs::path& job) {
  std::error_code ec;
  fs::remove_all(job / "groups", ec);
  Bundler(registry, view.graph().dir(), job).write(view.graph().file);
}

std::string task_assignment(const GraphView& view, const std::string& assignment) {
  const std::size_t eq = assignment.find('=');
  if (eq == std::string::npos) return assignment;
  ResolvedInput input;
  try {
    input = view.input(assignment.substr(0, eq));
  } catch (const Error&) {
    return assignment;  // validated already: time.start and the like
  }
  if (input.spec.role != InputRole::input_file) return assignment;
  json value = json::parse(assignment.substr(eq + 1), nullptr, false);
  const std::string text = value.is_string() ? value.get<std::string>() : assignment.substr(eq + 1);
  const fs::path p = text;
  if (p.empty() || p.is_absolute()) return assignment;
  return assignment.substr(0, eq) + "=" + json((view.graph().dir() / p).lexically_normal().string()).dump();
}

}  // namespace loom::runner
