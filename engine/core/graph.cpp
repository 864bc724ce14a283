#include "loom/graph.hpp"

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>

#include "literal.hpp"
#include "loom/suggest.hpp"

namespace loom {

namespace detail {

std::string pointer_escape(const std::string& token) {
  std::string out;
  for (char c : token) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

namespace {
void check_range(const InputSpec& spec, const json& j) {
  if (j.is_number()) {
    double v = j.get<double>();
    if ((spec.min && v < *spec.min) || (spec.max && v > *spec.max)) {
      std::ostringstream s;
      s << "value " << j.dump() << " is out of range: expected ";
      if (spec.min && spec.max) s << "between " << *spec.min << " and " << *spec.max;
      else if (spec.min) s << "at least " << *spec.min;
      else s << "at most " << *spec.max;
      throw Error(s.str());
    }
  } else if (j.is_array()) {
    for (const json& e : j) check_range(spec, e);
  }
}
}  // namespace

Value literal_value(const InputSpec& spec, const json& literal) {
  if (!spec.type->literal())
    throw Error(spec.type->name + " values cannot be written in a graph file: link this input " +
                "to a node output, e.g. {\"from\": \"ID.OUTPUT\"}");
  Value v;
  try {
    v = Value(spec.type, spec.type->from_json(literal));
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {  // a JSON library error in a conversion
    throw Error("expected " + spec.type->name + ", got " + describe_json(literal) + " (" + e.what() + ")");
  }
  if (!spec.choices.empty()) {
    const auto& s = v.as<std::string>();
    bool found = false;
    for (const auto& c : spec.choices) found = found || c == s;
    if (!found) {
      std::string list;
      for (const auto& c : spec.choices) list += (list.empty() ? "\"" : ", \"") + c + "\"";
      throw Error("\"" + s + "\" is not one of the choices: " + list);
    }
  }
  if (spec.min || spec.max) check_range(spec, literal);
  return v;
}

}  // namespace detail

namespace {

// At most this many issues are printed; the rest are counted.
constexpr std::size_t kIssuesShown = 100;

std::string issues_text(const std::string& file, const std::vector<GraphIssue>& issues) {
  std::string text;
  for (std::size_t k = 0; k < issues.size() && k < kIssuesShown; ++k) {
    const GraphIssue& i = issues[k];
    if (!text.empty()) text += "\n";
    text += file + ": " + (i.pointer.empty() ? "" : i.pointer + ": ") + i.message;
  }
  if (issues.size() > kIssuesShown)
    text += "\n" + file + ": ... and " + std::to_string(issues.size() - kIssuesShown) + " more issues";
  return text;
}

// A JSON text's deepest nesting of arrays and objects, scanning past strings;
// stops counting once past `limit`.
std::size_t nesting_depth(std::string_view text, std::size_t limit) {
  std::size_t depth = 0, deepest = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
      if (deepest > limit) return deepest;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return deepest;
}

bool valid_utf8(std::string_view s) {
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    std::size_t n = c < 0x80 ? 0 : (c >> 5) == 6 ? 1 : (c >> 4) == 14 ? 2 : (c >> 3) == 30 ? 3 : 9;
    if (n == 9 || (n > 0 && i + n >= s.size())) return false;
    for (std::size_t k = 1; k <= n; ++k)
      if ((static_cast<unsigned char>(s[i + k]) >> 6) != 2) return false;
    // Overlong forms and surrogates.
    if (n == 1 && c < 0xC2) return false;
    if (n == 2) {
      const auto d = static_cast<unsigned char>(s[i + 1]);
      if ((c == 0xE0 && d < 0xA0) || (c == 0xED && d >= 0xA0)) return false;
    }
    if (n == 3) {
      const auto d = static_cast<unsigned char>(s[i + 1]);
      if ((c == 0xF0 && d < 0x90) || c > 0xF4 || (c == 0xF4 && d >= 0x90)) return false;
    }
    i += n + 1;
  }
  return true;
}

// Parses JSON text into `out`. Any failure (syntax, a number beyond double,
// invalid UTF-8, nesting beyond kMaxJsonDepth) is an issue message, never an
// exception of the JSON library.
std::optional<std::string> parse_json_text(std::string_view text, json& out) {
  if (nesting_depth(text, kMaxJsonDepth) > kMaxJsonDepth)
    return "nested deeper than " + std::to_string(kMaxJsonDepth) + " arrays/objects";
  try {
    out = json::parse(text);
    return std::nullopt;
  } catch (const json::exception& e) {
    std::string what = e.what();
    auto p = what.find("] ");
    std::string message = p == std::string::npos ? what : what.substr(p + 2);
    if (message.size() > 300) message = message.substr(0, 300) + "...";
    return "not valid JSON: " + message;
  } catch (const std::exception& e) {
    return std::string("not valid JSON: ") + e.what();
  }
}

std::string cut(const std::string& s, std::size_t n) { return s.size() > n ? s.substr(0, n) + "..." : s; }

std::string node_pointer(const std::string& id) { return "/nodes/" + detail::pointer_escape(id); }
std::string input_pointer(const std::string& id, const std::string& input) {
  return node_pointer(id) + "/inputs/" + detail::pointer_escape(input);
}

}  // namespace

std::optional<Link> parse_link(std::string_view text) {
  const auto dot = text.find('.');
  if (dot == std::string_view::npos || dot == 0 || dot + 1 == text.size()) return std::nullopt;
  return Link{std::string(text.substr(0, dot)), std::string(text.substr(dot + 1))};
}

GraphError::GraphError(std::string file, std::vector<GraphIssue> issues)
    : Error(issues_text(file, issues)), file_(std::move(file)), issues_(std::move(issues)) {}

namespace {

// The "time" object; throws GraphError with /time pointers.
TimeRange parse_time(const json& t) {
  std::vector<GraphIssue> issues;
  TimeRange r;
  if (!t.is_object())
    throw GraphError("", {{"/time", "expected {\"start\": 1, \"end\": 48, \"fps\": 24}, got " + describe_json(t)}});
  for (const auto& [key, value] : t.items())
    if (key != "start" && key != "end" && key != "fps")
      issues.push_back({"/time/" + detail::pointer_escape(key), "unknown key (expected \"start\", \"end\" or \"fps\")"});
  auto frame = [&](const char* key, int fallback) {
    if (!t.contains(key)) return fallback;
    const json& v = t[key];
    if (!v.is_number_integer() || v.get<long long>() < -1000000000LL || v.get<long long>() > 1000000000LL) {
      issues.push_back({std::string("/time/") + key, "expected a frame number (an integer), got " + describe_json(v)});
      return fallback;
    }
    return static_cast<int>(v.get<long long>());
  };
  r.start = frame("start", 1);
  r.end = frame("end", r.start);
  if (t.contains("fps")) {
    const json& v = t["fps"];
    if (!v.is_number() || !(v.get<double>() > 0) || v.get<double>() > 1e6)
      issues.push_back({"/time/fps", "expected frames per second (a number above 0), got " + describe_json(v)});
    else
      r.fps = v.get<double>();
  }
  if (r.end < r.start)
    issues.push_back({"/time/end", "the end frame " + std::to_string(r.end) + " is before the start frame " +
                                       std::to_string(r.start)});
  if (!issues.empty()) throw GraphError("", issues);
  return r;
}

json time_to_json(const TimeRange& r) { return {{"start", r.start}, {"end", r.end}, {"fps", r.fps}}; }

}  // namespace

Graph parse_graph(const json& doc, const std::filesystem::path& file) {
  Graph g;
  g.file = file;
  std::vector<GraphIssue> issues;
  auto fail = [&](std::string pointer, std::string message) {
    issues.push_back({std::move(pointer), std::move(message)});
  };
  const std::string name = file.empty() ? "<graph>" : file.string();

  if (!doc.is_object()) throw GraphError(name, {{"", "expected a JSON object, got " + describe_json(doc)}});
  for (const auto& [key, value] : doc.items())
    if (key != "loom" && key != "seed" && key != "nodes" && key != "description" && key != "time" && key != "ui")
      fail("/" + detail::pointer_escape(key),
           "unknown key (expected \"loom\", \"seed\", \"time\", \"nodes\", \"description\" or \"ui\")");
  if (doc.contains("ui")) g.ui = doc["ui"];
  if (doc.contains("time")) {
    try {
      g.time = parse_time(doc["time"]);
    } catch (const GraphError& e) {
      for (const auto& i : e.issues()) fail(i.pointer, i.message);
    }
  }
  if (!doc.contains("loom"))
    fail("/loom", "missing: a graph file starts with {\"loom\": 1, ...}");
  else if (!doc["loom"].is_number_integer() || doc["loom"].get<long long>() != kGraphFormatVersion)
    fail("/loom", "expected format version 1, got " + describe_json(doc["loom"]) +
                      (doc["loom"].is_number_integer() && doc["loom"].get<long long>() > 1
                           ? ": this file is from a newer Loom"
                           : ""));
  if (doc.contains("seed")) {
    const json& seed = doc["seed"];
    if (!seed.is_number_unsigned() && !(seed.is_number_integer() && seed.get<long long>() >= 0))
      fail("/seed", "expected a non-negative integer, got " + describe_json(doc["seed"]));
    else
      g.seed = doc["seed"].get<std::uint64_t>();
  }
  if (!doc.contains("nodes") || !doc["nodes"].is_object()) {
    fail("/nodes", doc.contains("nodes") ? "expected an object of nodes by id, got " +
                                               describe_json(doc["nodes"])
                                         : "missing: the nodes, as {\"ID\": {\"type\": ...}}");
    throw GraphError(name, issues);
  }

  for (const auto& [id, node] : doc["nodes"].items()) {
    const std::string np = node_pointer(id);
    if (id.empty() || id.find('.') != std::string::npos) {
      fail(np, "node ids must be non-empty and contain no '.' (links are written \"ID.OUTPUT\")");
      continue;
    }
    if (!node.is_object()) {
      fail(np, "expected a node object {\"type\": ..., \"inputs\": {...}}, got " + describe_json(node));
      continue;
    }
    GraphNode n;
    n.id = id;
    for (const auto& [key, value] : node.items())
      if (key != "type" && key != "inputs" && key != "ui")
        fail(np + "/" + detail::pointer_escape(key),
             "unknown key (expected \"type\", \"inputs\" or \"ui\")");
    if (!node.contains("type") || !node["type"].is_string())
      fail(np + "/type", node.contains("type") ? "expected a node type name, got " + describe_json(node["type"])
                                               : "missing: every node needs a \"type\"");
    else
      n.type = node["type"].get<std::string>();
    if (node.contains("ui")) n.ui = node["ui"];
    if (node.contains("inputs")) {
      if (!node["inputs"].is_object()) {
        fail(np + "/inputs", "expected an object of inputs by name, got " + describe_json(node["inputs"]));
      } else {
        for (const auto& [input, value] : node["inputs"].items()) {
          InputBinding b;
          if (value.is_object() && value.contains("from")) {
            const std::string ip = input_pointer(id, input) + "/from";
            if (value.size() != 1) fail(input_pointer(id, input), "a link has only the key \"from\"");
            const json& from = value["from"];
            auto link = from.is_string() ? parse_link(from.get<std::string>()) : std::nullopt;
            if (!link) {
              fail(ip, "expected \"ID.OUTPUT\", got " + describe_json(from));
              continue;
            }
            b.link = std::move(*link);
          } else {
            b.literal = value;
          }
          n.inputs.emplace(input, std::move(b));
        }
      }
    }
    g.nodes.emplace(id, std::move(n));
  }
  if (!issues.empty()) throw GraphError(name, issues);
  return g;
}

bool link_compatible(const TypeInfo& from, const TypeInfo& to) {
  return from.storage == to.storage || is_any(from) || is_any(to);
}

Graph load_graph_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw GraphError(file.string(), {{"", "cannot open the file"}});
  std::stringstream buffer;
  buffer << in.rdbuf();
  json doc;
  if (auto problem = parse_json_text(buffer.str(), doc)) throw GraphError(file.string(), {{"", *problem}});
  return parse_graph(doc, std::filesystem::absolute(file));
}

Graph parse_graph_text(std::string_view text, const std::filesystem::path& file) {
  json doc;
  if (auto problem = parse_json_text(text, doc)) throw GraphError(file.empty() ? "<graph>" : file.string(), {{"", *problem}});
  return parse_graph(doc, file);
}

void validate_graph(const Graph& g, const Registry& registry, const std::string& searched,
                    const std::vector<std::string>& known_types) {
  std::vector<GraphIssue> issues;
  auto fail = [&](std::string pointer, std::string message) {
    issues.push_back({std::move(pointer), std::move(message)});
  };
  const std::string name = g.file.empty() ? "<graph>" : g.file.string();

  for (const auto& [id, n] : g.nodes) {
    const NodeType* t = registry.find(n.type);
    if (!t) {
      std::vector<std::string> known = known_types;
      for (const NodeType* r : registry.all()) known.push_back(r->spec.name);
      fail(node_pointer(id) + "/type", unknown_node_type_message(n.type, known, searched));
      continue;
    }
    for (const auto& [input, b] : n.inputs) {
      const InputSpec* spec = t->spec.find_input(input);
      const std::string ip = input_pointer(id, input);
      if (!spec) {
        std::string known;
        for (const auto& s : t->spec.inputs) known += (known.empty() ? "" : ", ") + s.name;
        fail(ip, "unknown input \"" + input + "\" of " + n.type +
                     (known.empty() ? " (it has no inputs)" : " (its inputs: " + known + ")"));
        continue;
      }
      if (b.link) {
        auto up = g.nodes.find(b.link->node);
        if (up == g.nodes.end()) {
          fail(ip + "/from", "links to unknown node \"" + b.link->node + "\"");
          continue;
        }
        const NodeType* ut = registry.find(up->second.type);
        if (!ut) continue;  // reported at that node
        int o = ut->spec.output_index(b.link->output);
        if (o < 0) {
          std::string known;
          for (const auto& s : ut->spec.outputs) known += (known.empty() ? "" : ", ") + s.name;
          fail(ip + "/from", "node \"" + b.link->node + "\" (" + ut->spec.name + ") has no output \"" +
                                 b.link->output + "\" (its outputs: " + (known.empty() ? "none" : known) + ")");
          continue;
        }
        const TypeInfo* have = ut->spec.outputs[static_cast<std::size_t>(o)].type;
        if (!link_compatible(*have, *spec->type))
          fail(ip + "/from", "type mismatch: " + b.link->node + "." + b.link->output + " is " +
                                 have->name + " but input \"" + input + "\" expects " + spec->type->name);
      } else {
        try {
          detail::literal_value(*spec, b.literal);
        } catch (const Error& e) {
          fail(ip, e.what());
        }
      }
    }
    for (const InputSpec& spec : t->spec.inputs)
      if (spec.required() && !n.inputs.count(spec.name))
        fail(node_pointer(id) + "/inputs",
             "missing required input \"" + spec.name + "\" (" + spec.type->name + ": " +
                 spec.description + ")");
  }

  // Cycles: iterative DFS over links. Each link that closes a cycle is
  // reported with a path of at most a few nodes, and only the first
  // kCyclesShown of them: a graph with thousands of links into one loop gets a
  // short, readable answer.
  constexpr std::size_t kCyclesShown = 10, kPathShown = 8;
  std::size_t cycles = 0;
  enum Mark { unseen, active, done };
  std::map<std::string, Mark> mark;
  std::map<std::string, std::size_t> depth;  // stack position of active nodes
  for (const auto& [root, unused] : g.nodes) {
    if (mark[root] != unseen) continue;
    struct Frame {
      const GraphNode* node;
      std::map<std::string, InputBinding>::const_iterator next;
    };
    std::vector<Frame> stack{{&g.nodes.at(root), g.nodes.at(root).inputs.begin()}};
    mark[root] = active;
    depth[root] = 0;
    while (!stack.empty()) {
      Frame& f = stack.back();
      if (f.next == f.node->inputs.end()) {
        mark[f.node->id] = done;
        stack.pop_back();
        continue;
      }
      const auto& [input, b] = *f.next++;
      if (!b.link || !g.nodes.count(b.link->node)) continue;
      Mark& m = mark[b.link->node];
      if (m == active) {
        if (++cycles > kCyclesShown) continue;
        const std::size_t from = depth[b.link->node], length = stack.size() - from;
        std::string path = cut(b.link->node, 60);
        for (std::size_t k = from + 1; k < stack.size(); ++k) {
          if (length > kPathShown && k == from + kPathShown / 2) {
            path += " → ... (" + std::to_string(length - kPathShown) + " more)";
            k = stack.size() - kPathShown / 2;
          }
          path += " → " + cut(stack[k].node->id, 60);
        }
        path += " → " + cut(b.link->node, 60);
        fail(input_pointer(f.node->id, input) + "/from",
             "cycle of " + std::to_string(length) + " node" + (length == 1 ? "" : "s") + ": " + path);
      } else if (m == unseen) {
        m = active;
        depth[b.link->node] = stack.size();
        const GraphNode& up = g.nodes.at(b.link->node);
        stack.push_back({&up, up.inputs.begin()});
      }
    }
  }
  if (cycles > kCyclesShown)
    fail("/nodes", std::to_string(cycles - kCyclesShown) + " more links close cycles (not listed)");
  if (!issues.empty()) throw GraphError(name, issues);
}

void set_input(Graph& g, const std::string& assignment) {
  if (!valid_utf8(assignment))
    throw GraphError("--set", {{"", "the assignment is not valid UTF-8 text"}});
  auto eq = assignment.find('=');
  auto dot = assignment.find('.');
  if (eq == std::string::npos || dot == std::string::npos || dot > eq)
    throw GraphError("--set", {{"", "expected ID.INPUT=VALUE, got \"" + cut(assignment, 80) + "\""}});
  std::string id = assignment.substr(0, dot);
  std::string input = assignment.substr(dot + 1, eq - dot - 1);
  std::string text = assignment.substr(eq + 1);
  auto it = g.nodes.find(id);
  json value;
  if (parse_json_text(text, value)) {
    // Not JSON: plain words are a string, but a value that looks like JSON
    // and fails (deep nesting, 1e400) is an error, not silently a string.
    const auto first = text.find_first_not_of(" \t");
    const bool looks_json = first != std::string::npos &&
                            std::string("[{\"-0123456789").find(text[first]) != std::string::npos;
    if (looks_json) {
      json ignored;
      throw GraphError("--set", {{input_pointer(id, input), *parse_json_text(text, ignored)}});
    }
    value = text;
  }
  if (it == g.nodes.end() && id == "time") {
    json t = g.time ? time_to_json(*g.time) : json::object();
    t[input] = value;
    try {
      g.time = parse_time(t);
    } catch (const GraphError& e) {
      throw GraphError("--set " + assignment, e.issues());
    }
    return;
  }
  if (it == g.nodes.end())
    throw GraphError(g.file.string(), {{node_pointer(id), "--set names unknown node \"" + cut(id, 80) + "\""}});
  InputBinding b;
  if (value.is_object() && value.contains("from") && value["from"].is_string()) {
    auto link = parse_link(value["from"].get<std::string>());
    if (!link) throw GraphError("--set", {{"", "expected {\"from\": \"ID.OUTPUT\"}, got " + cut(text, 80)}});
    b.link = std::move(*link);
  } else {
    b.literal = value;
  }
  it->second.inputs[input] = std::move(b);
}

json graph_to_json(const Graph& g) {
  json nodes = json::object();
  for (const auto& [id, n] : g.nodes) {
    json inputs = json::object();
    for (const auto& [name, b] : n.inputs)
      inputs[name] = b.link ? json{{"from", b.link->node + "." + b.link->output}} : b.literal;
    json node = {{"type", n.type}};
    if (!inputs.empty()) node["inputs"] = inputs;
    if (!n.ui.is_null()) node["ui"] = n.ui;
    nodes[id] = node;
  }
  json doc = {{"loom", kGraphFormatVersion}, {"seed", g.seed}, {"nodes", nodes}};
  if (g.time) doc["time"] = time_to_json(*g.time);
  if (!g.ui.is_null()) doc["ui"] = g.ui;
  return doc;
}

std::vector<std::string> node_types_used(const Graph& g) {
  std::set<std::string> types;
  for (const auto& [id, n] : g.nodes) types.insert(n.type);
  return {types.begin(), types.end()};
}

}  // namespace loom
