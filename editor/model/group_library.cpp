#include "group_library.hpp"

#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

namespace loom::editor {

namespace fs = std::filesystem;

namespace {

bool ends_with(const std::string& text, const std::string& tail) {
  return text.size() >= tail.size() && text.compare(text.size() - tail.size(), tail.size(), tail) == 0;
}

fs::path shipped_library() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed = exe.parent_path().parent_path() / "share" / "loom" / "graphs" / "lib";
    if (fs::is_directory(installed, ec)) return installed;
  }
  return LOOM_SOURCE_GRAPH_LIB;
}

}  // namespace

std::vector<fs::path> group_library_folders() {
  std::vector<fs::path> folders;
  if (const char* path = std::getenv("LOOM_GRAPH_PATH")) {
    std::stringstream list(path);
    for (std::string entry; std::getline(list, entry, ':');)
      if (!entry.empty()) folders.emplace_back(entry);
  }
  folders.push_back(shipped_library());
  return folders;
}

std::vector<LibraryGroup> list_library_groups(const std::vector<fs::path>& folders) {
  std::map<std::string, fs::path> found;
  for (const fs::path& folder : folders) {
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(folder, ec)) {
      const fs::path& file = entry.path();
      if (file.extension() == ".json" && entry.is_regular_file(ec))
        found.emplace(file.stem().string(), file);  // the first folder wins
    }
  }
  std::vector<LibraryGroup> groups;
  for (const auto& [name, file] : found) groups.push_back({name, file});
  return groups;
}

std::optional<fs::path> resolve_group_file(const std::string& type, const fs::path& graph_dir,
                                           const std::vector<fs::path>& folders) {
  std::error_code ec;
  if (ends_with(type, ".json")) {
    const fs::path file = fs::path(type).is_absolute() ? fs::path(type) : graph_dir / type;
    if (fs::is_regular_file(file, ec)) return file;
    return std::nullopt;
  }
  if (type.empty() || type.find('/') != std::string::npos) return std::nullopt;
  for (const fs::path& folder : folders)
    if (fs::is_regular_file(folder / (type + ".json"), ec)) return folder / (type + ".json");
  return std::nullopt;
}

namespace {

// A level's nodes as a version-1 graph: a Repeat node's own keys ("body",
// "cache_iterations") are not version 1's.
json as_version_1(const json& nodes) {
  json plain = nodes;
  if (plain.is_object())
    for (auto& [id, node] : plain.items())
      if (node.is_object())
        for (const char* key : {"body", "cache_iterations"}) node.erase(key);
  return {{"loom", kGraphFormatVersion}, {"nodes", plain}};
}

void check_level(const json& nodes, const fs::path& file, const std::string& pointer) {
  try {
    parse_graph(as_version_1(nodes), file);
  } catch (const GraphError& e) {
    std::vector<GraphIssue> issues = e.issues();
    for (GraphIssue& issue : issues) issue.pointer = pointer + issue.pointer;
    throw GraphError(e.file(), issues);
  }
}

// Whether the engine refused the file's version (its other issues may be
// version 2's keys, which the level-by-level check then covers).
bool refused_for_version(const GraphError& e) {
  for (const GraphIssue& issue : e.issues())
    if (issue.pointer == "/loom") return true;
  return false;
}

}  // namespace

void check_graph_structure(const json& document, const fs::path& file) {
  try {
    parse_graph(document, file);
    return;
  } catch (const GraphError& e) {
    const json version = document.is_object() ? document.value("loom", json()) : json();
    if (!refused_for_version(e) || version != 2) throw;
  }
  json top = document;
  top.erase("groups");
  top.erase("inputs");
  top.erase("outputs");
  check_level(top.value("nodes", json()), file, "");
  top.erase("nodes");
  top["loom"] = kGraphFormatVersion;
  top["nodes"] = json::object();
  parse_graph(top, file);  // seed, time, description, ui
  const json groups = document.value("groups", json::object());
  if (!groups.is_object()) throw GraphError(file.string(), {{"/groups", "expected an object of group definitions"}});
  for (const auto& [name, group] : groups.items()) {
    const std::string pointer = (json::json_pointer("/groups") / name).to_string();
    if (!group.is_object() || !group.contains("nodes"))
      throw GraphError(file.string(), {{pointer, "expected a group: {\"inputs\", \"outputs\", \"nodes\"}"}});
    check_level(group["nodes"], file, pointer);
  }
}

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
