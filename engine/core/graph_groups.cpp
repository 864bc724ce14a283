// Groups (format version 2), expanded at load into the flat Graph. Each group
// definition (inline under "groups", or a group file) is expanded once into a
// body: a Graph of its inner nodes with ids relative to the group, and its
// interface. An instance splices the body in under "INSTANCE.", records its
// interface, and the values given to it are fed to the inner inputs.
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#include "graph_groups.hpp"
#include "graph_parse.hpp"
#include "json_text.hpp"
#include "loom/input_file.hpp"
#include "repeat.hpp"

namespace loom::detail {

namespace fs = std::filesystem;

namespace {

// A file whose nodes are being expanded: the graph itself or a group file.
struct Scope {
  fs::path file;
  std::string shown;  // how issues name it; empty for the graph's own file
  std::shared_ptr<const json> doc;
};

// A group definition found for a node's type.
struct GroupRef {
  Scope scope;
  const json* def = nullptr;
  std::string base;      // JSON pointer of the definition in its file ("" for a group file)
  std::string identity;  // file#name: what self-reference is checked against
  std::string name;      // what seeds its inner nodes
};

bool is_json_path(const std::string& type) { return type.size() > 5 && type.compare(type.size() - 5, 5, ".json") == 0; }

bool object_has(const json& j, const char* key) { return j.is_object() && j.contains(key); }

const std::set<std::string> kInterfaceKeys = {"type", "default", "min", "max", "choices",
                                              "optional", "description", "to"};

class Expander {
 public:
  Expander(const fs::path& top, Issues& issues) : top_dir_(top.empty() ? fs::path() : top.parent_path()),
                                                  issues_(issues) {
    if (const char* text = std::getenv("LOOM_MAX_GROUP_NODES"); text && *text) {
      char* end = nullptr;
      const unsigned long long n = std::strtoull(text, &end, 10);
      if (*end == '\0' && n > 0 && text[0] != '-') node_limit_ = static_cast<std::size_t>(n);
      else issues_.push_back({"", std::string("LOOM_MAX_GROUP_NODES=") + text + ": expected a whole number above 0"});
    }
  }

  Graph level(const Scope& scope, const json& def, const std::string& base);
  std::vector<fs::path> files_read() const {
    std::vector<fs::path> files;
    for (const auto& [path, doc] : files_) files.emplace_back(path);
    return files;
  }
  // The graph being loaded is the outermost group of the chain.
  void enter(const fs::path& file) {
    if (!file.empty()) chain_.emplace_back(file.lexically_normal().string(), shown_name(file));
  }

 private:
  fs::path top_dir_;
  Issues& issues_;
  std::map<std::string, std::shared_ptr<const Graph>> bodies_;
  std::vector<std::pair<std::string, std::string>> chain_;  // identities being expanded (and shown), outermost first
  std::map<std::string, fs::path> found_;  // group files found by (folder, type)
  std::map<std::string, std::shared_ptr<const json>> files_;
  std::size_t node_limit_ = kMaxGroupNodes, made_ = 0;  // nodes (and instances) made by splicing bodies
  bool over_limit_ = false;  // reported once; nothing more is expanded

  void issue(const Scope& s, std::string pointer, std::string message) {
    issues_.push_back({std::move(pointer), std::move(message), s.shown});
  }
  std::string shown_name(const fs::path& file) const;
  std::shared_ptr<const json> load_file(const fs::path& file, const Scope& from, const std::string& pointer);
  std::optional<GroupRef> resolve(const std::string& type, const Scope& scope, const std::string& pointer);
  std::shared_ptr<const Graph> body(const GroupRef& ref, const Scope& from, const std::string& pointer);
  void add_node(Graph& g, const Scope& scope, const std::string& base, const std::string& id, const json& node,
                std::vector<std::string>& own);
  void add_instance(Graph& g, GraphNode n, const Graph& body);
  bool within_node_limit(const Graph& body, const Scope& scope, const std::string& pointer);
  void resolve_own_links(Graph& g, const Scope& scope, const std::vector<std::string>& own);
  void feed_instances(Graph& g, const Scope& scope, const std::vector<std::string>& own);
  GroupInterface parse_interface(const Graph& g, const Scope& scope, const json& def, const std::string& base);
  GroupInput parse_input_declaration(const Graph& g, const Scope& scope, const std::string& name, const json& d,
                                     const std::string& p, const GroupInterface& so_far);
};

std::string Expander::shown_name(const fs::path& file) const {
  if (!top_dir_.empty()) {
    const fs::path rel = file.lexically_relative(top_dir_);
    if (!rel.empty() && *rel.begin() != "..") return rel.string();
  }
  return file.string();
}

std::shared_ptr<const json> Expander::load_file(const fs::path& file, const Scope& from, const std::string& pointer) {
  const std::string key = file.string();
  if (auto it = files_.find(key); it != files_.end()) return it->second;
  std::error_code ec;
  if (const std::uintmax_t size = fs::file_size(file, ec); !ec && size > kMaxGroupFileBytes) {
    issue(from, pointer, "the group file " + file.string() + " is " + std::to_string(size >> 20) + " MiB, more than the " +
                             std::to_string(kMaxGroupFileBytes >> 20) + " MiB a group file may hold (it holds nodes, "
                             "not data: large values belong in input files)");
    return nullptr;
  }
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  auto doc = std::make_shared<json>();
  if (!in) {
    issue(from, pointer, "cannot read the group file " + file.string());
    return nullptr;
  }
  if (auto problem = parse_json_text(text.str(), *doc)) {
    issues_.push_back({"", *problem, shown_name(file)});
    return nullptr;
  }
  if (!doc->is_object() || !doc->contains("nodes") || !(*doc)["nodes"].is_object() ||
      !doc->contains("loom") || (*doc)["loom"] != kGroupsFormatVersion) {
    issues_.push_back({"", "a group file is a graph file with \"loom\": 2, \"nodes\" and its \"inputs\"/\"outputs\"",
                       shown_name(file)});
    return nullptr;
  }
  files_[key] = doc;
  return doc;
}

std::optional<GroupRef> Expander::resolve(const std::string& type, const Scope& scope, const std::string& pointer) {
  static const json none = json::object();
  const json& groups = scope.doc->contains("groups") ? scope.doc->at("groups") : none;
  if (groups.is_object() && groups.contains(type))
    return GroupRef{scope, &groups.at(type), "/groups/" + pointer_escape(type), scope.file.string() + "#" + type, type};
  auto [found, fresh] = found_.emplace(scope.file.parent_path().string() + "\n" + type, fs::path());
  if (fresh) found->second = find_group_file(type, scope.file);
  const fs::path file = found->second;
  // A group file naming its own bare name means the node type it shadows
  // (Math.json using Math); validation reports the clash where it is used.
  if (!file.empty() && file == scope.file.lexically_normal() && !is_json_path(type)) return std::nullopt;
  if (file.empty()) {
    const std::string kind = not_a_regular_file(scope.file.empty() ? fs::path(type) : scope.file.parent_path() / type);
    if (is_json_path(type) && !kind.empty())
      issue(scope, pointer, "group file \"" + type + "\" is " + kind + ", not a file: a group file is a regular "
                                "file of JSON");
    else if (is_json_path(type))
      issue(scope, pointer, "group file \"" + type + "\" not found (a path is relative to the folder of " +
                                (scope.file.empty() ? std::string("the graph") : scope.file.string()) + ")");
    return std::nullopt;
  }
  auto doc = load_file(file, scope, pointer);
  if (!doc) return GroupRef{};  // reported; def stays null
  Scope s{file, shown_name(file), doc};
  return GroupRef{s, doc.get(), "", file.lexically_normal().string(), file.stem().string()};
}

std::shared_ptr<const Graph> Expander::body(const GroupRef& ref, const Scope& from, const std::string& pointer) {
  const std::string shown = ref.base.empty() ? ref.scope.shown : (ref.scope.shown.empty() ? "" : ref.scope.shown + "#") + ref.name;
  for (std::size_t k = 0; k < chain_.size(); ++k) {
    if (chain_[k].first != ref.identity) continue;
    std::string path;
    for (std::size_t j = k; j < chain_.size(); ++j) path += chain_[j].second + " → ";
    issue(from, pointer, "group \"" + ref.name + "\" uses itself: " + path + shown);
    return nullptr;
  }
  if (auto it = bodies_.find(ref.identity); it != bodies_.end()) return it->second;
  if (over_limit_) return nullptr;  // past the node limit (reported): expand nothing more
  if (chain_.size() >= kMaxGroupDepth) {
    issue(from, pointer, "groups nest more than " + std::to_string(kMaxGroupDepth) + " levels deep here (" +
                             chain_.front().second + " → ... → " + shown + "): expanding recurses once per level; "
                             "flatten some of the groups");
    return nullptr;
  }
  if (!ref.def->is_object() || !ref.def->contains("nodes") || !(*ref.def)["nodes"].is_object()) {
    issue(ref.scope, ref.base.empty() ? "/nodes" : ref.base, "a group needs \"nodes\": {\"ID\": {...}}");
    return nullptr;
  }
  chain_.emplace_back(ref.identity, shown);
  auto g = std::make_shared<Graph>(level(ref.scope, *ref.def, ref.base));
  chain_.pop_back();
  if (!g->interface) g->interface.emplace();
  bodies_[ref.identity] = g;
  return g;
}

Link prefixed(const std::string& prefix, Link l) {
  l.node = prefix + l.node;
  return l;
}

// Splices a group's body under "ID.": its nodes, its nested instances, and
// the instance itself with the body's interface.
void Expander::add_instance(Graph& g, GraphNode n, const Graph& body) {
  const std::string prefix = n.id + ".";
  for (const auto& [id, inner] : body.nodes) {
    GraphNode c = inner;
    c.id = prefix + id;
    // Seeded by its own id in the group, so that grouping nodes (Ctrl+G, or
    // moving them into a group file) keeps their random numbers.
    if (c.seed_name.empty()) c.seed_name = id;
    for (auto& [name, b] : c.inputs)
      if (b.link) b.link = prefixed(prefix, *b.link);
    g.nodes.emplace(c.id, std::move(c));
  }
  auto prefix_interface = [&](GroupInterface in) {
    for (auto& [name, i] : in.inputs)
      for (auto& t : i.to) t = prefixed(prefix, t);
    for (auto& [name, o] : in.outputs) o = prefixed(prefix, o);
    return in;
  };
  for (const auto& [path, inst] : body.instances) {
    GroupInstance c = inst;
    c.interface = prefix_interface(c.interface);
    for (auto& [name, b] : c.given)
      if (b.link) b.link = prefixed(prefix, *b.link);
    g.instances.emplace(prefix + path, std::move(c));
  }
  g.instances[n.id] = GroupInstance{n.type, n.place, prefix_interface(*body.interface), std::move(n.inputs)};
}

// Counts the nodes an instance of `body` adds before they are copied.
bool Expander::within_node_limit(const Graph& body, const Scope& scope, const std::string& pointer) {
  const std::size_t more = body.nodes.size() + body.instances.size() + 1;
  if (!over_limit_ && more <= node_limit_ && made_ <= node_limit_ - more) {
    made_ += more;
    return true;
  }
  if (!over_limit_)
    issue(scope, pointer, "expanding the groups makes more than " + std::to_string(node_limit_) +
                              " nodes, the limit (a group used N times is N copies of its nodes, and nested groups "
                              "multiply): use fewer instances, or raise the limit with LOOM_MAX_GROUP_NODES=N");
  over_limit_ = true;
  return false;
}

void Expander::add_node(Graph& g, const Scope& scope, const std::string& base, const std::string& id,
                        const json& node, std::vector<std::string>& own) {
  const bool repeat = object_has(node, "type") && node["type"] == "Repeat";
  Issues local;
  auto n = parse_node(id, node, local, repeat);
  const std::string np = base + node_pointer(id);
  for (auto& i : local) issue(scope, base + i.pointer, i.message);
  if (!n) return;
  n->place = {scope.shown, np};
  if (n->type.empty()) return;  // reported
  if (repeat) {
    if (!node.contains("body") || !node["body"].is_string()) {
      issue(scope, np + "/body", "a Repeat node names its body group: \"body\": \"GROUP\"");
      return;
    }
    auto ref = resolve(node["body"].get<std::string>(), scope, np + "/body");
    if (!ref) issue(scope, np + "/body", "unknown group \"" + node["body"].get<std::string>() + "\"");
    auto b = ref && ref->def ? body(*ref, scope, np + "/body") : nullptr;
    if (!b) return;
    const json cache = node.value("cache_iterations", json(false));
    if (!cache.is_boolean()) issue(scope, np + "/cache_iterations", "expected true or false");
    n->repeat = make_repeat_body(node["body"].get<std::string>(), b, cache == true);
  } else if (auto ref = resolve(n->type, scope, np + "/type")) {
    auto b = ref->def ? body(*ref, scope, np + "/type") : nullptr;
    if (b && within_node_limit(*b, scope, np + "/type")) add_instance(g, std::move(*n), *b);
    own.push_back(id);
    return;
  }
  own.push_back(id);
  g.nodes.emplace(id, std::move(*n));
}

// "group instance "look" has no output "picture" (its outputs: image)"
std::string no_output_message(const Graph& g, const Link& link) {
  Link l = link;
  for (auto it = g.instances.find(l.node); it != g.instances.end(); it = g.instances.find(l.node)) {
    auto out = it->second.interface.outputs.find(l.output);
    if (out == it->second.interface.outputs.end()) {
      std::string known;
      for (const auto& [name, unused] : it->second.interface.outputs) known += (known.empty() ? "" : ", ") + name;
      return "group instance \"" + l.node + "\" (" + it->second.type + ") has no output \"" + l.output +
             "\" (its outputs: " + (known.empty() ? "none" : known) + ")";
    }
    l = out->second;
  }
  return "no output \"" + link.output + "\"";
}

void Expander::resolve_own_links(Graph& g, const Scope& scope, const std::vector<std::string>& own) {
  auto resolve_all = [&](std::map<std::string, InputBinding>& inputs, const std::string& np) {
    for (auto& [name, b] : inputs) {
      if (!b.link) continue;
      auto to = follow_instance_outputs(g, *b.link);
      if (!to) issue(scope, np + "/inputs/" + pointer_escape(name) + "/from", no_output_message(g, *b.link));
      else b.link = *to;
    }
  };
  for (const std::string& id : own) {
    if (auto it = g.nodes.find(id); it != g.nodes.end()) resolve_all(it->second.inputs, it->second.place.pointer);
    else if (auto in = g.instances.find(id); in != g.instances.end()) resolve_all(in->second.given, in->second.place.pointer);
  }
}

// Whether the group being expanded feeds an instance's input from its own
// interface (given when the group is used).
bool fed_directly_by_interface(const Graph& g, const std::string& id, const std::string& input) {
  if (!g.interface) return false;
  for (const auto& [name, in] : g.interface->inputs)
    for (const Link& t : in.to)
      if (t.node == id && t.output == input) return true;
  return false;
}

// The values given to each instance of this level (or its interface's
// defaults) fed to the inner inputs they name.
void Expander::feed_instances(Graph& g, const Scope& scope, const std::vector<std::string>& own) {
  for (const std::string& id : own) {
    auto it = g.instances.find(id);
    if (it == g.instances.end()) continue;
    const GroupInstance inst = it->second;
    for (const auto& [name, b] : inst.given)
      if (!inst.interface.inputs.count(name)) {
        std::string known;
        for (const auto& [k, unused] : inst.interface.inputs) known += (known.empty() ? "" : ", ") + k;
        issue(scope, inst.place.pointer + "/inputs/" + pointer_escape(name),
              "unknown input \"" + name + "\" of group " + inst.type + " (its inputs: " +
                  (known.empty() ? "none" : known) + ")");
      }
    for (const auto& [name, input] : inst.interface.inputs) {
      auto given = inst.given.find(name);
      InputBinding b;
      if (given != inst.given.end()) b = given->second;
      else if (input.declaration.contains("default")) b.literal = input.declaration["default"];
      else if (input.declaration.value("optional", false) == true || fed_directly_by_interface(g, id, name))
        continue;
      else {
        issue(scope, inst.place.pointer + "/inputs", "missing required input \"" + name + "\" of group " + inst.type);
        continue;
      }
      for (const Link& t : input.to) try {
          feed_input(g, t, b, false);
        } catch (const Error& e) {
          issues_.push_back({input.place.pointer, e.what(), input.place.file});
        }
    }
  }
}

// The interface input of `in` that already feeds `target`, or "".
std::string feeder(const GroupInterface& in, const Link& target) {
  for (const auto& [name, input] : in.inputs)
    for (const Link& t : input.to)
      if (t.node == target.node && t.output == target.output) return name;
  return "";
}

GroupInput Expander::parse_input_declaration(const Graph& g, const Scope& scope, const std::string& name,
                                             const json& d, const std::string& p, const GroupInterface& so_far) {
  GroupInput gi{d, {}, {scope.shown, p}};
  if (name.empty() || name.find('.') != std::string::npos) issue(scope, p, "input names are non-empty and hold no '.'");
  for (auto it = d.begin(); it != d.end(); ++it)
    if (!kInterfaceKeys.count(it.key()))
      issue(scope, p + "/" + pointer_escape(it.key()),
            "unknown key (expected type, default, min, max, choices, optional, description or to)");
  const json& to = d["to"];
  for (std::size_t k = 0; k < to.size(); ++k) {
    auto l = to[k].is_string() ? parse_link(to[k].get<std::string>()) : std::nullopt;
    if (!l || !(g.nodes.count(l->node) || g.instances.count(l->node))) {
      issue(scope, p + "/to/" + std::to_string(k),
            l ? "names unknown node \"" + l->node + "\" of the group" : "expected \"NODE.INPUT\", got " + describe_json(to[k]));
      continue;
    }
    if (const std::string other = feeder(so_far, *l); !other.empty()) {
      issue(scope, p + "/to/" + std::to_string(k),
            "interface inputs \"" + other + "\" and \"" + name + "\" both feed " + link_text(*l) +
                ": an input takes one value (feed it from one of them)");
      continue;
    }
    gi.to.push_back(*l);
  }
  gi.declaration.erase("to");
  gi.read = make_read_declaration(name);
  return gi;
}

GroupInterface Expander::parse_interface(const Graph& g, const Scope& scope, const json& def, const std::string& base) {
  GroupInterface in;
  if (def.contains("description") && def["description"].is_string()) in.description = def["description"];
  const json inputs = def.value("inputs", json::object()), outputs = def.value("outputs", json::object());
  if (!inputs.is_object()) issue(scope, base + "/inputs", "expected an object of interface inputs by name");
  if (!outputs.is_object()) issue(scope, base + "/outputs", "expected an object of interface outputs by name");
  for (auto it = inputs.begin(); inputs.is_object() && it != inputs.end(); ++it) {
    const std::string p = base + "/inputs/" + pointer_escape(it.key());
    const json& d = it.value();
    if (!d.is_object() || !d.contains("type") || !d["type"].is_string() || !d.contains("to") || !d["to"].is_array())
      issue(scope, p, "expected {\"type\": TYPE, \"to\": [\"NODE.INPUT\", ...], ...}");
    else
      in.inputs.emplace(it.key(), parse_input_declaration(g, scope, it.key(), d, p, in));
  }
  for (auto it = outputs.begin(); outputs.is_object() && it != outputs.end(); ++it) {
    const std::string p = base + "/outputs/" + pointer_escape(it.key());
    const json& d = it.value();
    std::optional<Link> l;
    if (object_has(d, "from") && d["from"].is_string()) l = parse_link(d["from"].get<std::string>());
    auto to = l && (g.nodes.count(l->node) || g.instances.count(l->node)) ? follow_instance_outputs(g, *l) : std::nullopt;
    if (!to) {
      issue(scope, p + "/from",
            l ? "names no output of the group's nodes: \"" + link_text(*l) + "\""
              : "expected {\"from\": \"NODE.OUTPUT\"}");
      continue;
    }
    in.outputs.emplace(it.key(), *to);
    in.output_places.emplace(it.key(), SourcePlace{scope.shown, p});
  }
  return in;
}

Graph Expander::level(const Scope& scope, const json& def, const std::string& base) {
  Graph g;
  std::vector<std::string> own;
  for (const auto& [id, node] : def["nodes"].items()) add_node(g, scope, base, id, node, own);
  resolve_own_links(g, scope, own);
  if (def.contains("inputs") || def.contains("outputs")) g.interface = parse_interface(g, scope, def, base);
  feed_instances(g, scope, own);
  return g;
}

}  // namespace

std::optional<Link> follow_instance_outputs(const Graph& g, Link link) {
  for (auto it = g.instances.find(link.node); it != g.instances.end(); it = g.instances.find(link.node)) {
    auto out = it->second.interface.outputs.find(link.output);
    if (out == it->second.interface.outputs.end()) return std::nullopt;
    link = out->second;
  }
  return link;
}

void feed_input(Graph& g, const Link& target, const InputBinding& binding, bool replace) {
  if (auto n = g.nodes.find(target.node); n != g.nodes.end()) {
    auto [it, fresh] = n->second.inputs.emplace(target.output, binding);
    if (!fresh && !replace)
      throw Error("input \"" + target.output + "\" of inner node \"" + target.node +
                  "\" is fed by the group's interface: leave it unset in the node");
    it->second = binding;
    return;
  }
  auto inst = g.instances.find(target.node);
  if (inst == g.instances.end()) throw Error("no node \"" + target.node + "\" to feed");
  auto in = inst->second.interface.inputs.find(target.output);
  if (in == inst->second.interface.inputs.end())
    throw Error("group instance \"" + target.node + "\" has no input \"" + target.output + "\"");
  inst->second.given[target.output] = binding;
  const std::vector<Link> to = in->second.to;
  for (const Link& t : to) feed_input(g, t, binding, true);
}

std::vector<Link> interface_targets(const Graph& g, const GroupInput& input) {
  std::vector<Link> out;
  for (const Link& t : input.to) {
    auto inst = g.instances.find(t.node);
    auto in = inst == g.instances.end() ? nullptr : &inst->second.interface.inputs;
    if (!in) {
      out.push_back(t);
    } else if (auto it = in->find(t.output); it != in->end()) {
      for (const Link& inner : interface_targets(g, it->second)) out.push_back(inner);
    }
  }
  return out;
}

void expand_groups(const json& doc, Graph& g, Issues& issues) {
  Expander e(g.file, issues);
  e.enter(g.file);
  Scope top{g.file, "", std::make_shared<json>(doc)};
  if (doc.contains("groups") && !doc["groups"].is_object())
    issues.push_back({"/groups", "expected an object of group definitions by name"});
  Graph flat = e.level(top, *top.doc, "");
  g.nodes = std::move(flat.nodes);
  g.instances = std::move(flat.instances);
  g.interface = std::move(flat.interface);
  g.group_files = e.files_read();
  if (!g.interface) return;
  // Run on its own, a group file's inputs take their defaults.
  for (const auto& [name, input] : g.interface->inputs) {
    if (!input.declaration.contains("default")) continue;
    InputBinding b;
    b.literal = input.declaration["default"];
    for (const Link& t : input.to) try {
        feed_input(g, t, b, false);
      } catch (const Error& ex) {
        issues.push_back({input.place.pointer, ex.what()});
      }
  }
}

}  // namespace loom::detail
