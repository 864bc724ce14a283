// The engine's one view of a prepared graph (loom/graph_view.hpp): node kinds,
// addresses, sinks, the stages of a run and the files a graph is made from.
#include "loom/graph_view.hpp"

#include <set>

#include "graph_groups.hpp"
#include "loom/suggest.hpp"
#include "repeat.hpp"

namespace loom {

namespace fs = std::filesystem;

const char* to_string(NodeKind kind) {
  switch (kind) {
    case NodeKind::plugin: return "plugin";
    case NodeKind::python: return "python";
    case NodeKind::repeat: return "repeat";
    case NodeKind::group: return "group";
  }
  return "?";
}

namespace {

// The instance's interface as a node type; outputs typed by the inner outputs.
std::unique_ptr<NodeType> interface_type(const Graph& g, const GroupInstance& inst, const Registry& registry) {
  auto type = std::make_unique<NodeType>();
  NodeSpec& spec = type->spec;
  spec.name = inst.type;
  spec.plugin = "group";
  spec.description = inst.interface.description;
  for (const auto& [name, input] : inst.interface.inputs) {
    if (const InputSpec* read = input.spec()) {
      spec.inputs.push_back(*read);
    } else {  // reported by validation; the view keeps the name
      InputSpec s;
      s.name = name;
      spec.inputs.push_back(std::move(s));
    }
  }
  for (const auto& [name, from] : inst.interface.outputs) {
    auto n = g.nodes.find(from.node);
    const NodeType* t = n == g.nodes.end() ? nullptr : detail::node_type_of(n->second, registry);
    const int o = t ? t->spec.output_index(from.output) : -1;
    const OutputSpec* inner = o < 0 ? nullptr : &t->spec.outputs[static_cast<std::size_t>(o)];
    spec.outputs.push_back({name, inner ? inner->description : "", inner ? inner->type : nullptr});
  }
  return type;
}

std::vector<std::string> every_id(const Graph& g) {
  std::vector<std::string> ids;
  for (const auto& [id, n] : g.nodes) ids.push_back(id);
  for (const auto& [id, i] : g.instances) ids.push_back(id);
  return ids;
}

std::string names_of_inputs(const NodeSpec& spec) {
  std::string known;
  for (const auto& s : spec.inputs) known += (known.empty() ? "" : ", ") + s.name;
  return known.empty() ? "none" : known;
}

std::string names_of_outputs(const NodeSpec& spec) {
  std::string known;
  for (const auto& s : spec.outputs) known += (known.empty() ? "" : ", ") + s.name;
  return known.empty() ? "none" : known;
}

}  // namespace

GraphView::GraphView(const Graph& graph, const Registry& registry) : graph_(graph), registry_(registry) {
  for (const auto& [path, inst] : graph.instances) instance_types_[path] = interface_type(graph, inst, registry);
}

GraphView::~GraphView() = default;

bool GraphView::has(const std::string& id) const { return graph_.nodes.count(id) || graph_.instances.count(id); }

NodeKind GraphView::kind(const std::string& id) const {
  if (graph_.instances.count(id)) return NodeKind::group;
  auto n = graph_.nodes.find(id);
  if (n == graph_.nodes.end()) {
    std::string near;
    for (const auto& s : near_names(id, every_id(graph_)))
      near += (near.empty() ? " (did you mean " : ", ") + ("\"" + s + "\"");
    throw Error("no node \"" + id + "\" in the graph" + (near.empty() ? "" : near + "?)"));
  }
  if (n->second.repeat) return NodeKind::repeat;
  return n->second.type.rfind("py.", 0) == 0 ? NodeKind::python : NodeKind::plugin;
}

const NodeType& GraphView::type(const std::string& id) const {
  if (kind(id) == NodeKind::group) return *instance_types_.at(id);
  const NodeType* t = detail::node_type_of(graph_.nodes.at(id), registry_);
  if (!t)
    throw Error("node \"" + id + "\": unknown type \"" + graph_.nodes.at(id).type + "\" (the graph was not validated)");
  return *t;
}

std::vector<std::string> GraphView::inner_nodes(const std::string& instance) const {
  std::vector<std::string> ids;
  if (!graph_.instances.count(instance)) return ids;
  // An instance's inner nodes are spliced in under "PATH." (graph_groups.cpp).
  const std::string prefix = instance + ".";
  for (auto it = graph_.nodes.lower_bound(prefix);
       it != graph_.nodes.end() && it->first.compare(0, prefix.size(), prefix) == 0; ++it)
    ids.push_back(it->first);
  return ids;
}

std::vector<std::string> GraphView::sinks() const {
  std::vector<std::string> ids;
  for (const auto& [id, n] : graph_.nodes)
    if (const NodeType* t = detail::node_type_of(n, registry_); t && t->spec.sink) ids.push_back(id);
  return ids;
}

ResolvedInput GraphView::input(const std::string& address) const {
  const auto link = parse_link(address);
  if (!link) throw Error("expected ID.INPUT, got \"" + address + "\"");
  ResolvedInput r;
  r.node = link->node;
  r.input = link->output;
  if (!has(r.node) && r.node == "time") {
    static const std::set<std::string> fields = {"start", "end", "fps"};
    if (!fields.count(r.input)) throw Error("\"" + address + "\": the graph's time has start, end and fps");
    r.time = true;
    r.spec.name = r.input;
    r.spec.type = r.input == "fps" ? &type_of<double>() : &type_of<int>();
    return r;
  }
  r.kind = kind(r.node);
  const NodeType& t = type(r.node);
  const InputSpec* spec = t.spec.find_input(r.input);
  if (!spec)
    throw Error("\"" + address + "\": " + (r.kind == NodeKind::group ? "group instance \"" : "node \"") + r.node +
                "\" (" + t.spec.name + ") has no input \"" + r.input +
                "\" (its inputs: " + names_of_inputs(t.spec) + ")");
  r.spec = *spec;
  return r;
}

std::vector<ResolvedOutput> GraphView::outputs(const std::string& address) const {
  std::vector<ResolvedOutput> out;
  std::string id = address, output;
  if (!has(id)) {
    const auto link = parse_link(address);
    if (!link || !has(link->node)) {
      kind(link ? link->node : address);  // throws, naming the near ids
      throw Error("expected ID or ID.OUTPUT, got \"" + address + "\"");
    }
    id = link->node;
    output = link->output;
  }
  const NodeKind k = kind(id);
  const NodeSpec& spec = type(id).spec;
  if (!output.empty() && spec.output_index(output) < 0)
    throw Error("\"" + address + "\": " + (k == NodeKind::group ? "group instance \"" : "node \"") + id + "\" (" +
                spec.name + ") has no output \"" + output + "\" (its outputs: " + names_of_outputs(spec) + ")");
  if (k == NodeKind::group) {
    for (const auto& o : spec.outputs)
      if (output.empty() || o.name == output) {
        const Link l = *detail::follow_instance_outputs(graph_, {id, o.name});
        out.push_back({link_text(id, o.name), {l.node, l.output}});
      }
    return out;
  }
  if (!output.empty()) return {{link_text(id, output), {id, output}}};
  // A node named whole: under its id, unless the id holds dots itself (then
  // "ID.OUTPUT" each, which no other address could mean).
  if (k != NodeKind::repeat && id.find('.') == std::string::npos) return {{id, {id, ""}}};
  for (const auto& o : spec.outputs) out.push_back({link_text(id, o.name), {id, o.name}});
  return out;
}

std::vector<ResolvedOutput> GraphView::outputs(const std::vector<Target>& targets) const {
  std::vector<ResolvedOutput> out;
  for (const Target& t : targets) {
    auto r = outputs(t.output.empty() ? t.node : link_text(t.node, t.output));
    out.insert(out.end(), r.begin(), r.end());
  }
  return out;
}

std::vector<std::string> GraphView::upstream(const std::vector<std::string>& targets) const {
  std::vector<std::string> roots;
  for (const auto& t : targets.empty() ? sinks() : targets)
    for (const auto& r : outputs(t)) roots.push_back(r.target.node);
  std::vector<std::string> order;
  std::set<std::string> done;
  std::vector<std::pair<std::string, bool>> stack;  // (node, its inputs already pushed)
  for (auto t = roots.rbegin(); t != roots.rend(); ++t) stack.push_back({*t, false});
  while (!stack.empty()) {
    auto [id, expanded] = stack.back();
    stack.pop_back();
    if (done.count(id)) continue;
    if (expanded) {
      done.insert(id);
      order.push_back(id);
      continue;
    }
    stack.push_back({id, true});
    for (const auto& [name, binding] : graph_.nodes.at(id).inputs)
      if (binding.link && !done.count(binding.link->node)) stack.push_back({binding.link->node, false});
  }
  return order;
}

RunStages GraphView::stages(const std::vector<std::string>& targets) const {
  RunStages s;
  for (const auto& t : targets.empty() ? sinks() : targets) {
    const auto resolved = outputs(t);
    const bool sequence = resolved.size() == 1 && resolved[0].target.output.empty() &&
                          type(resolved[0].target.node).spec.sequence;
    if (!sequence) {
      s.per_frame.push_back(t);
      continue;
    }
    s.sequences.push_back(t);
    for (const auto& [name, binding] : graph_.nodes.at(resolved[0].target.node).inputs)
      if (binding.link) s.per_frame.push_back(link_text(*binding.link));
  }
  for (const auto& id : upstream(targets))
    if (type(id).spec.simulation()) s.simulations.push_back(id);
  return s;
}

std::vector<fs::path> GraphView::files() const {
  std::vector<fs::path> files;
  std::set<fs::path> seen;
  auto add = [&](fs::path p) {
    p = fs::absolute(p).lexically_normal();
    if (seen.insert(p).second) files.push_back(p);
  };
  if (!graph_.file.empty()) add(graph_.file);
  for (const auto& f : graph_.group_files) add(f);
  for (const auto& [id, node] : graph_.nodes) {
    const NodeType* type = detail::node_type_of(node, registry_);
    if (!type) continue;
    for (const InputSpec& spec : type->spec.inputs) {
      auto it = node.inputs.find(spec.name);
      if (spec.role != InputRole::input_file || it == node.inputs.end() || it->second.link ||
          !it->second.literal.is_string())
        continue;
      fs::path p = it->second.literal.get<std::string>();
      if (!p.empty()) add(p.is_relative() ? graph_.dir() / p : p);
    }
    if (!type->spec.source_file.empty()) add(type->spec.source_file);
  }
  return files;
}

NodeType repeat_declaration(const NodeType& body, const std::string& body_name) {
  NodeType type = body;
  NodeSpec& spec = type.spec;
  spec.name = "Repeat";
  spec.description = "runs group " + body_name + " count times" +
                     (body.spec.description.empty() ? "" : " (" + body.spec.description + ")");
  for (const auto& s : spec.inputs)
    if (s.name == "count") throw Error("the body declares an input \"count\": Repeat's own input has that name");
  // "iteration" (Int or Float) is fed by Repeat itself: 0 .. count-1.
  std::vector<InputSpec> own;
  for (auto& s : spec.inputs)
    if (s.name != "iteration" || (s.type != &type_of<int>() && s.type != &type_of<double>()))
      own.push_back(std::move(s));
  spec.inputs.clear();
  spec.input<int>("count", 1, "how many times the body runs; 0 passes the threaded inputs through").at_least(0);
  for (auto& s : own) spec.inputs.push_back(std::move(s));
  for (auto& o : spec.outputs) o.description = "the body's output after the last iteration";
  return type;
}

std::vector<std::pair<std::string, Value>> named_outputs(const GraphView& view,
                                                        const std::map<std::string, std::vector<Value>>& outputs) {
  std::vector<std::pair<std::string, Value>> named;
  for (const auto& [name, values] : outputs) {
    if (values.size() == 1 && !view.has(name)) {
      named.emplace_back(name, values[0]);
      continue;
    }
    const auto& outputs = view.type(name).spec.outputs;
    for (std::size_t i = 0; i < values.size(); ++i)
      named.emplace_back(link_text(name, i < outputs.size() ? outputs[i].name : std::to_string(i)), values[i]);
  }
  return named;
}

std::vector<std::pair<std::string, std::vector<Value>>> named_outputs_per_frame(const GraphView& view,
                                                                                const EvalResult& result) {
  std::vector<std::pair<std::string, std::vector<Value>>> named;
  if (result.outputs_per_frame.empty()) {
    for (auto& [name, value] : named_outputs(view, result.outputs)) named.push_back({name, {value}});
    return named;
  }
  std::map<std::string, std::size_t> at;
  for (const auto& [name, frames] : result.outputs_per_frame)
    for (const auto& values : frames)
      for (auto& [output, value] : named_outputs(view, {{name, values}})) {
        auto [it, fresh] = at.emplace(output, named.size());
        if (fresh) named.push_back({output, {}});
        named[it->second].second.push_back(value);
      }
  return named;
}

}  // namespace loom
