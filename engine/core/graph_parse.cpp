// Graph files, structure only: JSON text to Graph and back. Checks against the
// registry are in graph_validate.cpp, --set in graph_set.cpp.
#include <algorithm>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>

#include "graph_groups.hpp"
#include "graph_parse.hpp"
#include "graph_time.hpp"
#include "json_text.hpp"
#include "loom/graph.hpp"
#include "loom/input_declaration.hpp"
#include "repeat.hpp"

namespace loom {

namespace {

// At most this many issues are printed; the rest are counted.
constexpr std::size_t kIssuesShown = 100;

std::string issues_text(const std::string& file, const std::vector<GraphIssue>& issues) {
  std::string text;
  for (std::size_t k = 0; k < issues.size() && k < kIssuesShown; ++k) {
    const GraphIssue& i = issues[k];
    if (!text.empty()) text += "\n";
    text += (i.source.empty() ? file : i.source) + ": " + (i.pointer.empty() ? "" : i.pointer + ": ") + i.message;
  }
  if (issues.size() > kIssuesShown)
    text += "\n" + file + ": ... and " + std::to_string(issues.size() - kIssuesShown) + " more issues";
  return text;
}

using Issues = std::vector<GraphIssue>;

// The format version: 1, or 2 for a file that uses groups.
int parse_version(const json& doc, Issues& issues) {
  if (!doc.contains("loom")) {
    issues.push_back({"/loom", "missing: a graph file starts with {\"loom\": 1, ...}"});
    return kGraphFormatVersion;
  }
  const json& v = doc["loom"];
  if (v.is_number_integer() && (v.get<long long>() == kGraphFormatVersion || v.get<long long>() == kGroupsFormatVersion))
    return v.get<int>();
  issues.push_back({"/loom", "expected format version 1 or 2, got " + describe_json(v) +
                                 (v.is_number_integer() && v.get<long long>() > kGroupsFormatVersion
                                      ? ": this file is from a newer Loom"
                                      : "")});
  return kGraphFormatVersion;
}

void parse_header(const json& doc, Graph& g, Issues& issues) {
  auto fail = [&](std::string pointer, std::string message) {
    issues.push_back({std::move(pointer), std::move(message)});
  };
  g.version = parse_version(doc, issues);
  const bool v2 = g.version == kGroupsFormatVersion;
  for (const auto& [key, value] : doc.items()) {
    const bool group_key = key == "groups" || key == "inputs" || key == "outputs";
    if (group_key && !v2)
      fail("/" + key, "\"" + key + "\" needs format version 2: write \"loom\": 2");
    else if (!group_key && key != "loom" && key != "seed" && key != "nodes" && key != "description" && key != "time" &&
             key != "ui")
      fail("/" + detail::pointer_escape(key),
           std::string("unknown key (expected \"loom\", \"seed\", \"time\", \"nodes\", \"description\"") +
               (v2 ? ", \"groups\", \"inputs\", \"outputs\"" : "") + " or \"ui\")");
  }
  if (doc.contains("ui")) g.ui = doc["ui"];
  if (doc.contains("time")) {
    try {
      g.time = detail::parse_time(doc["time"]);
    } catch (const GraphError& e) {
      for (const auto& i : e.issues()) issues.push_back(i);
    }
  }
  if (doc.contains("seed")) {
    const json& seed = doc["seed"];
    if (!seed.is_number_unsigned() && !(seed.is_number_integer() && seed.get<long long>() >= 0))
      fail("/seed", "expected a non-negative integer, got " + describe_json(seed));
    else
      g.seed = seed.get<std::uint64_t>();
  }
}

// One input of a node: a link {"from": "ID.OUTPUT"} or a literal.
std::optional<InputBinding> parse_input(const std::string& id, const std::string& input, const json& value,
                                        Issues& issues) {
  InputBinding b;
  if (!value.is_object() || !value.contains("from")) {
    b.literal = value;
    return b;
  }
  const std::string ip = detail::input_pointer(id, input);
  if (value.size() != 1) issues.push_back({ip, "a link has only the key \"from\""});
  const json& from = value["from"];
  auto link = from.is_string() ? parse_link(from.get<std::string>()) : std::nullopt;
  if (!link) {
    issues.push_back({ip + "/from", "expected \"ID.OUTPUT\", got " + describe_json(from)});
    return std::nullopt;
  }
  b.link = std::move(*link);
  return b;
}

}  // namespace

std::optional<GraphNode> detail::parse_node(const std::string& id, const json& node, Issues& issues, bool repeat) {
  const std::string np = detail::node_pointer(id);
  auto fail = [&](std::string pointer, std::string message) {
    issues.push_back({std::move(pointer), std::move(message)});
  };
  if (id.empty() || id.find('.') != std::string::npos) {
    fail(np, "node ids must be non-empty and contain no '.' (links are written \"ID.OUTPUT\")");
    return std::nullopt;
  }
  if (!node.is_object()) {
    fail(np, "expected a node object {\"type\": ..., \"inputs\": {...}}, got " + describe_json(node));
    return std::nullopt;
  }
  GraphNode n;
  n.id = id;
  for (const auto& [key, value] : node.items())
    if (key != "type" && key != "inputs" && key != "ui" && !(repeat && (key == "body" || key == "cache_iterations")))
      fail(np + "/" + detail::pointer_escape(key),
           repeat ? "unknown key (expected \"type\", \"body\", \"inputs\", \"cache_iterations\" or \"ui\")"
                  : "unknown key (expected \"type\", \"inputs\" or \"ui\")");
  if (!node.contains("type") || !node["type"].is_string())
    fail(np + "/type", node.contains("type") ? "expected a node type name, got " + describe_json(node["type"])
                                             : "missing: every node needs a \"type\"");
  else
    n.type = node["type"].get<std::string>();
  if (node.contains("ui")) n.ui = node["ui"];
  if (!node.contains("inputs")) return n;
  if (!node["inputs"].is_object()) {
    fail(np + "/inputs", "expected an object of inputs by name, got " + describe_json(node["inputs"]));
    return n;
  }
  for (const auto& [input, value] : node["inputs"].items())
    if (auto b = parse_input(id, input, value, issues)) n.inputs.emplace(input, std::move(*b));
  return n;
}

std::optional<Link> parse_link(std::string_view text) {
  const auto dot = text.rfind('.');
  if (dot == std::string_view::npos || dot == 0 || dot + 1 == text.size()) return std::nullopt;
  return Link{std::string(text.substr(0, dot)), std::string(text.substr(dot + 1))};
}

// A group input's declaration, read once it reads: value types register as
// plugins load, so a failure is not kept (it is asked again, and validation
// reports it after the plugins are in).
struct ReadDeclaration {
  std::string name;
  std::mutex mutex;
  std::optional<InputSpec> spec;
};

std::shared_ptr<ReadDeclaration> detail::make_read_declaration(const std::string& name) {
  auto r = std::make_shared<ReadDeclaration>();
  r->name = name;
  return r;
}

const InputSpec* GroupInput::spec(std::string* problem) const {
  if (!read) return nullptr;
  std::lock_guard<std::mutex> lock(read->mutex);
  if (read->spec) return &*read->spec;
  try {
    read->spec = input_spec_from_json(read->name, declaration);
    return &*read->spec;
  } catch (const Error& e) {
    if (problem) *problem = e.what();
    return nullptr;
  }
}

std::string link_text(std::string_view node, std::string_view member) {
  std::string text(node);
  text += '.';
  text += member;
  return text;
}

GraphError::GraphError(std::string file, std::vector<GraphIssue> issues)
    : Error(issues_text(file, issues)), file_(std::move(file)), issues_(std::move(issues)) {}

Graph parse_graph(const json& doc, const std::filesystem::path& file) {
  Graph g;
  g.file = file;
  Issues issues;
  const std::string name = file.empty() ? "<graph>" : file.string();
  if (!doc.is_object()) throw GraphError(name, {{"", "expected a JSON object, got " + describe_json(doc)}});
  parse_header(doc, g, issues);
  if (!doc.contains("nodes") || !doc["nodes"].is_object()) {
    issues.push_back({"/nodes", doc.contains("nodes")
                                    ? "expected an object of nodes by id, got " + describe_json(doc["nodes"])
                                    : "missing: the nodes, as {\"ID\": {\"type\": ...}}"});
    throw GraphError(name, issues);
  }
  if (g.version == kGroupsFormatVersion) {
    detail::expand_groups(doc, g, issues);
  } else {
    for (const auto& [id, node] : doc["nodes"].items())
      if (auto n = detail::parse_node(id, node, issues)) g.nodes.emplace(id, std::move(*n));
  }
  if (!issues.empty()) throw GraphError(name, issues);
  return g;
}

Graph load_graph_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw GraphError(file.string(), {{"", "cannot open the file"}});
  std::stringstream buffer;
  buffer << in.rdbuf();
  json doc;
  if (auto problem = detail::parse_json_text(buffer.str(), doc)) throw GraphError(file.string(), {{"", *problem}});
  return parse_graph(doc, std::filesystem::absolute(file));
}

Graph parse_graph_text(std::string_view text, const std::filesystem::path& file) {
  json doc;
  if (auto problem = detail::parse_json_text(text, doc))
    throw GraphError(file.empty() ? "<graph>" : file.string(), {{"", *problem}});
  return parse_graph(doc, file);
}

namespace detail {

json flat_graph_json(const Graph& g) {
  json nodes = json::object();
  for (const auto& [id, n] : g.nodes) {
    json inputs = json::object();
    for (const auto& [name, b] : n.inputs) inputs[name] = b.link ? json{{"from", link_text(*b.link)}} : b.literal;
    json node = {{"type", n.type}};
    if (!inputs.empty()) node["inputs"] = inputs;
    if (!n.ui.is_null()) node["ui"] = n.ui;
    nodes[id] = node;
  }
  json doc = {{"loom", kGraphFormatVersion}, {"seed", g.seed}, {"nodes", nodes}};
  if (g.time) doc["time"] = detail::time_to_json(*g.time);
  if (!g.ui.is_null()) doc["ui"] = g.ui;
  return doc;
}

}  // namespace detail

json graph_to_json(const Graph& g) {
  const bool repeat = std::any_of(g.nodes.begin(), g.nodes.end(), [](const auto& n) { return n.second.repeat != nullptr; });
  if (!g.instances.empty() || repeat || g.interface)
    throw Error((g.file.empty() ? std::string("the graph") : g.file.string()) +
                " uses groups or Repeat (\"loom\": 2), which the expanded graph cannot be written back as: "
                "write the document it was loaded from");
  return detail::flat_graph_json(g);
}

bool link_compatible(const TypeInfo& from, const TypeInfo& to) {
  return from.storage == to.storage || is_any(from) || is_any(to);
}

std::vector<std::string> node_types_used(const Graph& g) {
  std::set<std::string> types;
  for (const auto& [id, n] : g.nodes) {
    if (!n.repeat) {
      types.insert(n.type);
      continue;
    }
    for (const auto& t : node_types_used(*n.repeat->body)) types.insert(t);
  }
  return {types.begin(), types.end()};
}

}  // namespace loom
