// The Repeat node: runs a body group `count` times. Each iteration is an
// evaluation of the body's flat graph with the interface inputs given as
// values (hashed, not read): the initial values under the Repeat node's own
// hash, a threaded value under the hash of the body node that produced it.
// Iterations use a session of their own unless "cache_iterations" is set, so
// nothing of them outlives the Repeat node; inner nodes that do not depend on
// a threaded value are still computed once per Repeat run.
#include "repeat.hpp"

#include <algorithm>

#include "evaluation.hpp"
#include "graph_groups.hpp"
#include "graph_parse.hpp"
#include "loom/graph_view.hpp"
#include "loom/hash.hpp"

namespace loom::detail {

namespace {

// Everything about the body that its results depend on but the Repeat node's
// inputs do not say: its nodes, values and links, and their types' versions
// and builds. It enters the Repeat node's hash as its build.
std::uint64_t body_identity(const RepeatBody& r, const Registry& registry) {
  Hasher h;
  h.str(flat_graph_json(*r.body).dump()).pod(r.cache_iterations);
  for (const auto& [name, input] : r.body->interface->inputs) {
    h.str(name).str(input.declaration.dump());
    for (const Link& t : interface_targets(*r.body, input)) h.str(t.node).str(t.output);
  }
  for (const auto& [name, from] : r.body->interface->outputs) h.str(name).str(from.node).str(from.output);
  for (const auto& [id, n] : r.body->nodes) {
    h.str(n.seed_key());
    if (const NodeType* t = node_type_of(n, registry)) h.pod(t->spec.version).pod(t->spec.build);
  }
  return h.digest();
}

void inherit_flags(NodeSpec& spec, const Graph& body, const Registry& registry) {
  for (const auto& [id, n] : body.nodes) {
    const NodeType* t = node_type_of(n, registry);
    if (!t) continue;  // reported by validation
    if (t->spec.simulation()) throw Error("node \"" + id + "\" of the body is a simulation: a Repeat body cannot step time");
    spec.sink = spec.sink || t->spec.sink;
    spec.nondeterministic = spec.nondeterministic || t->spec.nondeterministic;
    spec.time_dependent = spec.time_dependent || t->spec.time_dependent;
  }
}

std::unique_ptr<NodeType> build_type(const RepeatBody& r, const Registry& registry) {
  auto type = std::make_unique<NodeType>(
      repeat_declaration(group_node_type(*r.body, r.body_type, "engine", registry), r.body_type));
  NodeSpec& spec = type->spec;
  inherit_flags(spec, *r.body, registry);
  spec.build = body_identity(r, registry);
  return type;
}

}  // namespace

std::shared_ptr<const RepeatBody> make_repeat_body(std::string body_type, std::shared_ptr<const Graph> body,
                                                   bool cache_iterations) {
  auto r = std::make_shared<RepeatBody>();
  r->body_type = std::move(body_type);
  r->body = std::move(body);
  r->cache_iterations = cache_iterations;
  return r;
}

const NodeType& repeat_node_type(const RepeatBody& r, const Registry& registry) {
  std::lock_guard lock(r.mutex);
  if (!r.type) r.type = build_type(r, registry);
  return *r.type;
}

namespace {

struct IterationValue {
  Value value;
  std::uint64_t hash = 0;
};

// One Repeat run: the body evaluated `count` times on `state`.
class RepeatRun {
 public:
  RepeatRun(Evaluation& outer, NodeState& s, Session::State& state)
      : outer_(outer), s_(s), state_(state), repeat_(*s.node->repeat), body_(*repeat_.body) {
    body_.file = outer.graph.file;  // paths in the body resolve as the graph's do
    body_.seed = outer.graph.seed;
    body_.time = outer.graph.time;
    options_ = outer.options;
    options_.observer = nullptr;  // the Repeat node reports progress for its body
    options_.targets.clear();
    if (!repeat_.cache_iterations) options_.disk_cache = nullptr;
    for (const auto& [name, input] : body_.interface->inputs) {
      targets_[name] = interface_targets(body_, input);
      if (name == "iteration") iteration_is_float_ = input.spec() && input.spec()->type == &type_of<double>();
    }
  }

  // Iteration i: the body's outputs, given the values of its inputs.
  std::map<std::string, IterationValue> iterate(int i, std::map<std::string, IterationValue> inputs) {
    if (targets_.count("iteration") && !inputs.count("iteration"))
      inputs["iteration"] = {iteration_is_float_ ? Value::make<double>(i) : Value::make<int>(i),
                             Hasher().str("iteration").pod(i).digest()};
    std::map<std::pair<std::string, std::string>, std::pair<Value, std::uint64_t>> by_input;
    for (const auto& [name, v] : inputs)
      for (const Link& t : targets_[name]) by_input[{t.node, t.output}] = {v.value, v.hash};
    if (!repeat_.cache_iterations) ++state_.generation;  // the outer session's is the outer frame's
    Evaluation e(state_, body_, options_, outer_.time);
    e.iteration_values = &by_input;
    e.scope = outer_.scoped_id(s_) + ".";
    e.build();
    std::vector<NodeIndex> roots;  // the body's outputs and its sinks (a body may only write files)
    for (const auto& [name, from] : body_.interface->outputs) roots.push_back(e.index.at(from.node));
    for (std::size_t n = 0; n < e.nodes.size(); ++n)
      if (e.nodes[n]->type->spec.sink) roots.push_back(n);
    e.execute(roots);
    for (std::size_t n = 0; n < e.nodes.size(); ++n)
      if (e.nodes[n]->type->spec.sink && !e.nodes[n]->ok) throw_failed(i, *e.nodes[n]);
    std::map<std::string, IterationValue> out;
    for (const auto& [name, from] : body_.interface->outputs) {
      NodeState& n = e.at(e.index.at(from.node));
      if (!n.ok) throw_failed(i, n);
      const int o = n.type->spec.output_index(from.output);
      out[name] = {n.outputs[static_cast<std::size_t>(o)], Hasher(n.hash).pod(o).digest()};
      s_.add_files(n.files);
    }
    if (!repeat_.cache_iterations) evict(state_, 0);
    return out;
  }

  [[noreturn]] static void throw_failed(int i, const NodeState& n) {
    throw Error("iteration " + std::to_string(i) + ": node \"" + n.node->id + "\" " + to_string(n.report.status) +
                (n.report.error.empty() ? "" : ": " + n.report.error));
  }

 private:
  Evaluation& outer_;
  NodeState& s_;
  Session::State& state_;
  const RepeatBody& repeat_;
  Graph body_;
  EvalOptions options_;
  std::map<std::string, std::vector<Link>> targets_;
  bool iteration_is_float_ = false;
};

// A body output threads to the next iteration when a body input has its name and type.
bool threaded(const NodeSpec& spec, const std::string& output) {
  const InputSpec* in = spec.find_input(output);
  const int o = spec.output_index(output);
  return in && o >= 0 && link_compatible(*spec.outputs[static_cast<std::size_t>(o)].type, *in->type) &&
         spec.outputs[static_cast<std::size_t>(o)].type->storage == in->type->storage;
}

}  // namespace

void run_repeat(Evaluation& outer, NodeState& s, Inputs& in, Outputs& out, Context& ctx) {
  const NodeSpec& spec = s.type->spec;
  const int count = in.get<int>("count");
  std::map<std::string, IterationValue> values;
  for (const InputSpec& i : spec.inputs)
    if (i.name != "count" && in.has(i.name))
      values[i.name] = {in.value(i.name), Hasher(s.hash).str("input").str(i.name).digest()};
  std::unique_ptr<Session::State> own;
  if (!s.node->repeat->cache_iterations) own = std::make_unique<Session::State>(outer.session.registry);
  RepeatRun run(outer, s, own ? *own : outer.session);
  std::map<std::string, IterationValue> result;
  for (int i = 0; i < count; ++i) {
    ctx.check_cancelled();
    result = run.iterate(i, values);
    for (const auto& [name, v] : result)
      if (threaded(spec, name)) values[name] = v;
    ctx.progress(i + 1, count, "iteration " + std::to_string(i + 1) + " of " + std::to_string(count));
  }
  for (const OutputSpec& o : spec.outputs) {
    if (count > 0) {
      out.set_value(o.name, result.at(o.name).value);
    } else if (threaded(spec, o.name) && values.count(o.name)) {
      out.set_value(o.name, values.at(o.name).value);
    } else {
      throw Error("count is 0 and output \"" + o.name + "\" is not threaded (no body input has its name and type): "
                  "it has no value");
    }
  }
}

const NodeType* node_type_of(const GraphNode& node, const Registry& registry) {
  if (!node.repeat) return registry.find(node.type);
  try {
    return &repeat_node_type(*node.repeat, registry);
  } catch (const Error&) {  // an invalid body: validation reports why (repeat_node_type)
    return nullptr;
  }
}

}  // namespace loom::detail
