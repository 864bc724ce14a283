#include "group_library.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>

namespace loom::editor {

namespace fs = std::filesystem;

std::vector<LibraryGroup> list_library_groups() {
  std::vector<LibraryGroup> groups;
  for (const fs::path& file : library_group_files()) groups.push_back({file.stem().string(), file});
  std::sort(groups.begin(), groups.end(), [](const LibraryGroup& a, const LibraryGroup& b) { return a.name < b.name; });
  return groups;
}

std::optional<fs::path> resolve_group_file(const std::string& type, const fs::path& graph_dir) {
  // find_group_file takes the naming file; "graph_dir/" names a file in graph_dir.
  fs::path file = find_group_file(type, graph_dir / "");
  if (file.empty()) return std::nullopt;
  return file;
}

void check_graph_structure(const json& document, const fs::path& file) { parse_graph(document, file); }

json read_json_file(const fs::path& file, std::string& text) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw GraphError(file.string(), {{"", "cannot open the file"}});
  std::stringstream contents;
  contents << in.rdbuf();
  text = contents.str();
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    throw GraphError(file.string(), {{"", std::string("not valid JSON: ") + e.what()}});
  }
}

json read_group_file(const fs::path& file) {
  std::string text;
  const json doc = read_json_file(file, text);
  if (!doc.is_object() || !doc.contains("nodes") || !doc["nodes"].is_object())
    throw GraphError(file.string(), {{"/nodes", "missing: a group file has a \"nodes\" object"}});
  for (const char* key : {"inputs", "outputs"})
    if (doc.contains(key) && !doc[key].is_object())
      throw GraphError(file.string(), {{std::string("/") + key, "expected an object of interface entries"}});
  return doc;
}

}  // namespace loom::editor
