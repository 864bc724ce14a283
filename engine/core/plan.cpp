// Building an evaluation from a graph: node states, input bindings,
// topological order, computation hashes.
#include "computation_hash.hpp"
#include "evaluation.hpp"

namespace loom::detail {

void Evaluation::build() {
  nodes.reserve(graph.nodes.size());
  for (const auto& [id, n] : graph.nodes) {
    index.emplace(id, nodes.size());
    auto s = std::make_unique<NodeState>();
    s->node = &n;
    s->type = session.registry.find(n.type);
    if (!s->type) throw Error("node \"" + id + "\": unknown type " + n.type + " (graph not validated)");
    nodes.push_back(std::move(s));
  }
  bind_inputs();
  hash_nodes(topological_order());
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
    s.seed = Hasher(graph.seed).str(s.node->id).digest();
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
