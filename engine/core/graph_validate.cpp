// Graph files against the registry: types, inputs, links, literal values,
// cycles and the depth of lazy chains. Every issue found is reported at once.
#include <map>
#include <set>

#include "graph_groups.hpp"
#include "group_validate.hpp"
#include "input_binding.hpp"
#include "json_text.hpp"
#include "loom/graph.hpp"
#include "loom/suggest.hpp"
#include "repeat.hpp"

namespace loom {

namespace {

using Issues = std::vector<GraphIssue>;

// Where a node was written: /nodes/ID of the graph, or its place in a group.
std::string node_base(const GraphNode& n) {
  return n.place.pointer.empty() ? detail::node_pointer(n.id) : n.place.pointer;
}
std::string input_base(const GraphNode& n, const std::string& input) {
  return node_base(n) + "/inputs/" + detail::pointer_escape(input);
}
// An issue at node n; inside a group the message names the node's path.
GraphIssue at_node(const GraphNode& n, std::string pointer, std::string message, std::string set_by = {}) {
  if (!n.place.pointer.empty()) message += " (node \"" + n.id + "\")";
  return {std::move(pointer), std::move(message), set_by.empty() ? n.place.file : set_by};
}

std::string names_of(const std::vector<InputSpec>& specs) {
  std::string known;
  for (const auto& s : specs) known += (known.empty() ? "" : ", ") + s.name;
  return known;
}

void validate_link(const Graph& g, const Registry& registry, const GraphNode& n, const InputSpec& spec,
                   const Link& link, Issues& issues) {
  const std::string ip = input_base(n, spec.name);
  auto up = g.nodes.find(link.node);
  if (up == g.nodes.end()) {
    issues.push_back(at_node(n, ip + "/from", "links to unknown node \"" + link.node + "\""));
    return;
  }
  const NodeType* ut = detail::node_type_of(up->second, registry);
  if (!ut) return;  // reported at that node
  const int o = ut->spec.output_index(link.output);
  if (o < 0) {
    std::string known;
    for (const auto& s : ut->spec.outputs) known += (known.empty() ? "" : ", ") + s.name;
    issues.push_back(at_node(n, ip + "/from", "node \"" + link.node + "\" (" + ut->spec.name + ") has no output \"" +
                                        link.output + "\" (its outputs: " + (known.empty() ? "none" : known) + ")"));
    return;
  }
  const TypeInfo* have = ut->spec.outputs[static_cast<std::size_t>(o)].type;
  if (!link_compatible(*have, *spec.type))
    issues.push_back(at_node(n, ip + "/from",
                             "type mismatch: " + link_text(link) + " is " + have->name + " but input \"" + spec.name +
                                 "\" expects " + spec.type->name));
}

// The inner inputs a group's own interface feeds (a group file validated on
// its own, a Repeat body): given when the group is used, not in the file.
std::set<std::pair<std::string, std::string>> own_interface_targets(const Graph& g) {
  std::set<std::pair<std::string, std::string>> fed;
  if (!g.interface) return fed;
  for (const auto& [name, input] : g.interface->inputs)
    for (const Link& t : detail::interface_targets(g, input)) fed.insert({t.node, t.output});
  return fed;
}

// The inner inputs the instances' interfaces feed: an unknown one among them
// is reported once, at the interface's "to" (validate_groups), not at a node
// input that the file does not write, once per instance.
std::set<std::pair<std::string, std::string>> fed_by_instances(const Graph& g) {
  std::set<std::pair<std::string, std::string>> fed;
  for (const auto& [path, inst] : g.instances)
    for (const auto& [name, input] : inst.interface.inputs)
      for (const Link& t : detail::interface_targets(g, input)) fed.insert({t.node, t.output});
  return fed;
}

void validate_node(const Graph& g, const Registry& registry, const GraphNode& n, const NodeType& t,
                   const std::set<std::pair<std::string, std::string>>& fed,
                   const std::set<std::pair<std::string, std::string>>& instance_fed, Issues& issues) {
  for (const auto& [input, b] : n.inputs) {
    const InputSpec* spec = t.spec.find_input(input);
    const std::string ip = input_base(n, input);
    if (!spec && (instance_fed.count({n.id, input}) || fed.count({n.id, input}))) continue;
    if (!spec) {
      const std::string known = names_of(t.spec.inputs);
      issues.push_back(at_node(n, ip, "unknown input \"" + input + "\" of " + n.type +
                                (known.empty() ? " (it has no inputs)" : " (its inputs: " + known + ")"),
                        b.set_by));
    } else if (b.link) {
      const std::size_t before = issues.size();
      validate_link(g, registry, n, *spec, *b.link, issues);
      if (!b.set_by.empty() && issues.size() > before) issues.back().source = b.set_by;
    } else {
      try {
        detail::literal_value(*spec, b.literal);
      } catch (const Error& e) {
        issues.push_back(at_node(n, ip, e.what(), b.set_by));
      }
    }
  }
  for (const InputSpec& spec : t.spec.inputs)
    if (spec.required() && !n.inputs.count(spec.name) && !fed.count({n.id, spec.name}))
      issues.push_back(at_node(n, node_base(n) + "/inputs", "missing required input \"" + spec.name + "\" (" +
                                                                spec.type->name + ": " + spec.description + ")"));
}

// Cycles: an iterative DFS over links. Each link that closes a cycle is
// reported with a path of at most a few nodes, and only the first
// kCyclesShown of them: a graph with thousands of links into one loop gets a
// short, readable answer. Returns how many links close cycles.
std::size_t find_cycles(const Graph& g, Issues& issues) {
  constexpr std::size_t kCyclesShown = 10, kPathShown = 8;
  std::size_t cycles = 0;
  enum Mark { unseen, active, done };
  std::map<std::string, Mark> mark;
  std::map<std::string, std::size_t> depth;  // stack position of active nodes
  struct Frame {
    const GraphNode* node;
    std::map<std::string, InputBinding>::const_iterator next;
  };
  auto report = [&](const std::vector<Frame>& stack, const std::string& to, const std::string& input) {
    const std::size_t from = depth[to], length = stack.size() - from;
    std::string path = detail::cut(to, 60);
    for (std::size_t k = from + 1; k < stack.size(); ++k) {
      if (length > kPathShown && k == from + kPathShown / 2) {
        path += " → ... (" + std::to_string(length - kPathShown) + " more)";
        k = stack.size() - kPathShown / 2;
      }
      path += " → " + detail::cut(stack[k].node->id, 60);
    }
    path += " → " + detail::cut(to, 60);
    const GraphNode& n = *stack.back().node;
    issues.push_back(at_node(n, input_base(n, input) + "/from",
                             "cycle of " + std::to_string(length) + " node" + (length == 1 ? "" : "s") + ": " + path));
  };
  for (const auto& [root, unused] : g.nodes) {
    if (mark[root] != unseen) continue;
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
        if (++cycles <= kCyclesShown) report(stack, b.link->node, input);
      } else if (m == unseen) {
        m = active;
        depth[b.link->node] = stack.size();
        const GraphNode& up = g.nodes.at(b.link->node);
        stack.push_back({&up, up.inputs.begin()});
      }
    }
  }
  if (cycles > kCyclesShown)
    issues.push_back({"/nodes", std::to_string(cycles - kCyclesShown) + " more links close cycles (not listed)"});
  return cycles;
}

// A lazy input is fetched from inside its node's body, so a chain of lazy
// links nests one evaluation in another: each is a few kilobytes of stack.
// Refuses chains longer than kMaxLazyChain (an acyclic graph: longest path
// by dynamic programming over a post-order).
void check_lazy_depth(const Graph& g, const Registry& registry, Issues& issues) {
  std::map<std::string, int> lazy_depth;  // of finished nodes
  for (const auto& [root, unused] : g.nodes) {
    if (lazy_depth.count(root)) continue;
    std::vector<std::pair<const GraphNode*, bool>> stack{{&g.nodes.at(root), false}};
    while (!stack.empty()) {
      auto [n, expanded] = stack.back();
      stack.pop_back();
      if (lazy_depth.count(n->id)) continue;
      const NodeType* t = detail::node_type_of(*n, registry);
      if (!expanded) {
        stack.push_back({n, true});
        for (const auto& [input, b] : n->inputs)
          if (b.link && g.nodes.count(b.link->node) && !lazy_depth.count(b.link->node))
            stack.push_back({&g.nodes.at(b.link->node), false});
        continue;
      }
      int deepest = 0;
      for (const auto& [input, b] : n->inputs) {
        if (!b.link || !lazy_depth.count(b.link->node)) continue;
        const InputSpec* spec = t ? t->spec.find_input(input) : nullptr;
        deepest = std::max(deepest, lazy_depth[b.link->node] + (spec && spec->lazy ? 1 : 0));
      }
      lazy_depth[n->id] = deepest;
      if (deepest == kMaxLazyChain + 1)
        issues.push_back(at_node(*n, node_base(*n),
                          "more than " + std::to_string(kMaxLazyChain) + " lazy inputs (e.g. Switch) are chained "
                          "up to this node: each nests one evaluation in another; split the chain or link fewer "
                          "lazy inputs in a row"));
    }
  }
}

}  // namespace

namespace {

// Every issue of g, and of the bodies of its Repeat nodes (each body once).
void collect_issues(const Graph& g, const Registry& registry, const std::string& searched,
                    const std::vector<std::string>& known_types, Issues& issues, std::set<const Graph*>& bodies) {
  const auto fed = own_interface_targets(g), instance_fed = fed_by_instances(g);
  for (const auto& [id, n] : g.nodes) {
    const NodeType* t = detail::node_type_of(n, registry);
    if (n.repeat && !t) try {
        detail::repeat_node_type(*n.repeat, registry);
      } catch (const Error& e) {  // a body whose interface is invalid, or that steps time
        issues.push_back(at_node(n, node_base(n) + "/body", e.what()));
      }
    if (n.repeat && bodies.insert(n.repeat->body.get()).second)
      collect_issues(*n.repeat->body, registry, searched, known_types, issues, bodies);
    if (t) {
      validate_node(g, registry, n, *t, fed, instance_fed, issues);
      continue;
    }
    if (n.repeat) continue;  // reported above
    std::vector<std::string> known = known_types;
    for (const NodeType* r : registry.all()) known.push_back(r->spec.name);
    issues.push_back(at_node(n, node_base(n) + "/type", unknown_node_type_message(n.type, known, searched)));
  }
  detail::validate_groups(g, registry, known_types, issues);
  if (find_cycles(g, issues) == 0) check_lazy_depth(g, registry, issues);
}

}  // namespace

void validate_graph(const Graph& g, const Registry& registry, const std::string& searched,
                    const std::vector<std::string>& known_types) {
  Issues issues;
  std::set<const Graph*> bodies;
  collect_issues(g, registry, searched, known_types, issues, bodies);
  if (!issues.empty()) throw GraphError(g.file.empty() ? "<graph>" : g.file.string(), issues);
}

}  // namespace loom
