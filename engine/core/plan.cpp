// Building an evaluation from a graph: node states, input bindings,
// topological order, computation hashes.
#include <filesystem>

#include "computation_hash.hpp"
#include "evaluation.hpp"
#include "literal.hpp"

namespace loom::detail {

void Evaluation::build() {
  nodes.reserve(graph.nodes.size());
  for (const auto& [id, n] : graph.nodes) {
    index.emplace(id, static_cast<int>(nodes.size()));
    auto s = std::make_unique<NodeState>();
    s->node = &n;
    s->type = session.registry.find(n.type);
    if (!s->type) throw Error("node \"" + id + "\": unknown type " + n.type + " (graph not validated)");
    nodes.push_back(std::move(s));
  }
  bind_inputs();
  hash_nodes(topological_order());
}

// Each declared input: a link, a literal (from the graph or the default, paths
// resolved against the graph's or the output folder), or unset.
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
                            : spec.default_value.is_null() ? nullptr
                                                           : &spec.default_value;
      if (!literal) continue;  // optional and unset
      b.kind = NodeState::Binding::literal;
      b.literal_value = literal_value(spec, *literal);
      if (spec.role != InputRole::value) {
        std::filesystem::path p = b.literal_value.as<std::string>();
        const auto& base = spec.role == InputRole::input_file ? graph_dir : options.output_dir;
        if (p.is_relative()) p = base / p;
        b.literal_value = Value::make<std::string>(p.lexically_normal().string());
      }
    }
  }
}

// Upstream before downstream: an iterative post-order DFS over links.
std::vector<int> Evaluation::topological_order() const {
  std::vector<int> order;
  std::vector<char> mark(nodes.size(), 0);
  for (int root = 0; root < static_cast<int>(nodes.size()); ++root) {
    if (mark[static_cast<std::size_t>(root)]) continue;
    std::vector<std::pair<int, std::size_t>> stack{{root, 0}};
    mark[static_cast<std::size_t>(root)] = 1;
    while (!stack.empty()) {
      auto& [n, next] = stack.back();
      const auto& ins = nodes[static_cast<std::size_t>(n)]->inputs;
      if (next == ins.size()) {
        order.push_back(n);
        stack.pop_back();
        continue;
      }
      const auto& b = ins[next++];
      if (b.kind == NodeState::Binding::link && !mark[static_cast<std::size_t>(b.upstream)]) {
        mark[static_cast<std::size_t>(b.upstream)] = 1;
        stack.emplace_back(b.upstream, 0);
      }
    }
  }
  return order;
}

void Evaluation::hash_nodes(const std::vector<int>& order) {
  const std::uint64_t run_salt = Hasher().pod(session.evaluations).str("nondeterministic").digest();
  for (int n : order) {
    NodeState& s = at(n);
    const NodeSpec& spec = s.type->spec;
    s.seed = Hasher(graph.seed).str(s.node->id).digest();
    s.hash = computation_hash(s, nodes, run_salt);
    s.cacheable = !spec.sink && !spec.nondeterministic;
  }
}

}  // namespace loom::detail
