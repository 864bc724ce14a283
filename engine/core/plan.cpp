// Building an evaluation from a graph: node states, input bindings,
// topological order, computation hashes.
#include "computation_hash.hpp"
#include "evaluation.hpp"
#include "graph_groups.hpp"
#include "repeat.hpp"

namespace loom::detail {

void Evaluation::build() {
  nodes.reserve(graph.nodes.size());
  for (const auto& [id, n] : graph.nodes) {
    index.emplace(id, nodes.size());
    auto s = std::make_unique<NodeState>();
    s->node = &n;
    s->type = node_type_of(n, session.registry);
    if (!s->type) throw Error("node \"" + id + "\": unknown type " + n.type + " (graph not validated)");
    nodes.push_back(std::move(s));
  }
  bind_inputs();
  if (!graph.instances.empty()) collect_interface_checks();
  const std::vector<NodeIndex> order = topological_order();
  hash_nodes(order);
  share_equal_results(order);
}

// Equal computations run once: a link to a cacheable node whose hash an
// earlier node (in topological order) has reads that node instead. Node ids
// are in every top-level node's seed, so only the inner nodes of two group
// instances fed equal values meet here; the second instance's copies are left
// without dependents and are pruned unless asked for.
void Evaluation::share_equal_results(const std::vector<NodeIndex>& order) {
  std::unordered_map<std::uint64_t, NodeIndex> first;
  std::vector<std::optional<NodeIndex>> same(nodes.size());
  bool any = false;
  for (NodeIndex n : order) {
    const NodeState& s = at(n);
    if (!s.cacheable || s.type->spec.simulation()) continue;
    auto [it, fresh] = first.emplace(s.hash, n);
    if (!fresh) same[n] = it->second, any = true;
  }
  if (!any) return;
  for (auto& sp : nodes)
    for (auto& b : sp->inputs)
      if (b.kind == NodeState::Binding::link && same[b.upstream]) b.upstream = *same[b.upstream];
}

// Each declared input: a link, a literal (from the graph or the default,
// bound by the one rule of input_binding.hpp), or unset.
void Evaluation::bind_inputs() {
  for (auto& sp : nodes) {
    NodeState& s = *sp;
    const auto& specs = s.type->spec.inputs;
    s.inputs.resize(specs.size());
    for (std::size_t i = 0; i < specs.size(); ++i) {
      const InputSpec& spec = specs[i];
      auto& b = s.inputs[i];
      auto it = s.node->inputs.find(spec.name);
      if (iteration_values && bind_iteration_value(s, spec, b)) continue;
      if (it != s.node->inputs.end() && it->second.link) {
        b.kind = NodeState::Binding::link;
        b.upstream = index.at(it->second.link->node);
        b.output = at(b.upstream).type->spec.output_index(it->second.link->output);
        continue;
      }
      const json* literal = it != s.node->inputs.end() ? &it->second.literal
                            : spec.has_default()                ? &spec.default_value
                                                                : nullptr;
      if (!literal) continue;  // optional and unset
      b.kind = NodeState::Binding::literal;
      try {
        b.literal_value = bind_value(spec, convert_literal(spec, *literal), place);
      } catch (const Error& e) {
        const bool set = it != s.node->inputs.end() && !it->second.set_by.empty();
        throw Error("node \"" + s.node->id + "\": " + e.what() + (set ? " (given by " + it->second.set_by + ")" : ""));
      }
    }
  }
}

void Evaluation::collect_interface_checks() {
  for (const auto& [path, inst] : graph.instances)
    for (const auto& [name, b] : inst.given) {
      auto in = inst.interface.inputs.find(name);
      if (!b.link || in == inst.interface.inputs.end()) continue;  // literals were checked by validation
      const InputSpec* spec = in->second.spec();                   // null only in a graph validation refuses
      if (!spec || (!spec->min && !spec->max && spec->choices.empty())) continue;
      for (const Link& t : interface_targets(graph, in->second)) {
        auto n = index.find(t.node);
        const int i = n == index.end() ? -1 : at(n->second).type->spec.input_index(t.output);
        if (i >= 0) interface_checks[{&at(n->second), i}].emplace_back(path, *spec);
      }
    }
}

void Evaluation::check_interface_inputs(const NodeState& s, int input, const Value& value) const {
  auto it = interface_checks.find({&s, input});
  if (it == interface_checks.end()) return;
  for (const auto& [path, spec] : it->second) try {
      check_declared(spec, value);
    } catch (const Error& e) {
      throw Error("input \"" + s.type->spec.inputs[static_cast<std::size_t>(input)].name + "\": group input \"" +
                  spec.name + "\" of " + path + ": " + e.what());
    }
}

// A Repeat body's input given its iteration's value: bound by the same rule as a linked value.
bool Evaluation::bind_iteration_value(const NodeState& s, const InputSpec& spec, NodeState::Binding& b) {
  auto given = iteration_values->find({s.node->id, spec.name});
  if (given == iteration_values->end()) return false;
  b.kind = NodeState::Binding::literal;
  b.iteration_hash = given->second.second;
  try {
    b.literal_value = bind_value(spec, given->second.first, place);
  } catch (const Error& e) {
    throw Error("node \"" + s.node->id + "\": " + e.what());
  }
  return true;
}

// Upstream before downstream: an iterative post-order DFS over links.
std::vector<NodeIndex> Evaluation::topological_order() const {
  std::vector<NodeIndex> order;
  std::vector<char> mark(nodes.size(), 0);
  for (NodeIndex root = 0; root < nodes.size(); ++root) {
    if (mark[root]) continue;
    std::vector<std::pair<NodeIndex, std::size_t>> stack{{root, 0}};
    mark[root] = 1;
    while (!stack.empty()) {
      auto& [n, next] = stack.back();
      const auto& ins = nodes[n]->inputs;
      if (next == ins.size()) {
        order.push_back(n);
        stack.pop_back();
        continue;
      }
      const auto& b = ins[next++];
      if (b.kind == NodeState::Binding::link && !mark[b.upstream]) {
        mark[b.upstream] = 1;
        stack.emplace_back(b.upstream, 0);
      }
    }
  }
  return order;
}

// Hashes in topological order (computation_hash.cpp has the rule). Past the
// start frame, a first pass at the start frame gives each simulation its chain.
void Evaluation::hash_nodes(const std::vector<NodeIndex>& order) {
  const std::uint64_t run_salt = Hasher().pod(session.evaluations).str("nondeterministic").digest();
  bool any_simulation = false;
  for (NodeIndex n : order) {
    NodeState& s = at(n);
    const NodeSpec& spec = s.type->spec;
    s.seed = Hasher(graph.seed).str(s.node->seed_key()).digest();
    s.cacheable = !spec.sink && !spec.nondeterministic;
    s.time_dependent = spec.time_dependent;
    for (const auto& b : s.inputs)
      if (b.kind == NodeState::Binding::link) s.time_dependent = s.time_dependent || at(b.upstream).time_dependent;
    if (spec.simulation()) {  // the declaration was checked when the type was registered
      any_simulation = true;
      s.state_input = spec.input_index(spec.state_input);
      s.state_output = spec.output_index(spec.state_output);
    }
  }
  auto pass = [&](const FrameTime& t) {
    for (NodeIndex n : order) {
      NodeState& s = at(n);
      if (s.type->spec.simulation()) {
        if (t.frame == time.start) s.chain = computation_hash(s, nodes, run_salt, t);
        s.hash = state_hash(s.chain, t.frame);
      } else {
        s.hash = computation_hash(s, nodes, run_salt, t);
      }
    }
  };
  if (any_simulation && time.frame != time.start) {
    FrameTime start = time;
    start.frame = time.start;
    pass(start);
  }
  pass(time);
}

}  // namespace loom::detail
