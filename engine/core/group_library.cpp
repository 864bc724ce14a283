// Group files as node types to list: `loom nodes`, docs/nodes.md and the
// editor's search show a group's interface like a C++ node's declaration.
#include <fstream>
#include <set>

#include "graph_groups.hpp"
#include "json_text.hpp"
#include "repeat.hpp"

namespace loom {

namespace fs = std::filesystem;

namespace {

void never_run(Inputs&, Outputs&, Context&) { throw Error("a group's inner nodes run, not the group"); }

// A graph file that declares an interface: a group file.
bool is_group_file(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  json doc;
  if (!in.good() && !in.eof()) return false;
  if (detail::parse_json_text(text, doc)) return false;
  return doc.is_object() && (doc.contains("inputs") || doc.contains("outputs"));
}

}  // namespace

std::vector<fs::path> library_group_files() {
  std::vector<fs::path> files;
  std::set<std::string> names;
  for (const fs::path& dir : graph_search_path()) {
    std::error_code ec;
    std::vector<fs::path> here;
    for (const auto& entry : fs::directory_iterator(dir, ec))
      if (entry.path().extension() == ".json" && entry.is_regular_file(ec)) here.push_back(entry.path());
    std::sort(here.begin(), here.end());
    for (const fs::path& f : here)
      if (!names.count(f.stem().string()) && is_group_file(f)) {
        names.insert(f.stem().string());
        files.push_back(f);
      }
  }
  return files;
}

NodeType group_node_type(const Graph& group, const std::string& name, const std::string& plugin,
                         const Registry& registry) {
  if (!group.interface) throw Error(name + ": not a group (no \"inputs\" or \"outputs\")");
  NodeType type;
  NodeSpec& spec = type.spec;
  spec.name = name;
  spec.plugin = plugin;
  spec.description = group.interface->description;
  for (const auto& [input, declared] : group.interface->inputs) {
    std::string problem;
    const InputSpec* read = declared.spec(&problem);
    if (!read) throw Error(name + ": interface input \"" + input + "\": " + problem);
    spec.inputs.push_back(*read);
  }
  for (const auto& [output, from] : group.interface->outputs) {
    auto n = group.nodes.find(from.node);
    const NodeType* t = n == group.nodes.end() ? nullptr : detail::node_type_of(n->second, registry);
    const int o = t ? t->spec.output_index(from.output) : -1;
    if (o < 0) throw Error(name + ": output \"" + output + "\" comes from " + link_text(from) + ", unknown");
    const OutputSpec& inner = t->spec.outputs[static_cast<std::size_t>(o)];
    spec.outputs.push_back({output, inner.description, inner.type});
  }
  type.run = never_run;
  return type;
}

}  // namespace loom
