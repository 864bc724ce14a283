// Host API (the runner, the editor, Python), not for plugin authors.
//
// The engine's one view of a loaded, validated graph: what each node is, what
// an "ID.INPUT" or "ID.OUTPUT" address names, which nodes are sinks, which
// stages a run has and which files the graph is made from or reads. Every
// driver — `loom run`, --sweep/--record, `loom submit`, MPI, --watch, the
// Python module, the editor — asks this view; none looks a type up in the
// registry or splits an address itself (docs/architecture.md, "One view of
// a graph").
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "loom/evaluator.hpp"
#include "loom/graph.hpp"

namespace loom {

// What a node of the graph is: a plugin's node type, a type a Python module
// provides ("py.MODULE.NAME"), the engine's Repeat, or an instance of a
// group (its inner nodes are nodes of the graph under "PATH.INNER").
enum class NodeKind { plugin, python, repeat, group };
LOOM_API const char* to_string(NodeKind kind);

// An "ID.INPUT" address: a node's input, a group instance's interface input
// or the graph's time ("time.start", "time.end", "time.fps").
struct ResolvedInput {
  std::string node, input;
  NodeKind kind = NodeKind::plugin;  // of `node` (unused for time)
  bool time = false;
  InputSpec spec;  // the input's declaration (the interface's, for a group input)
};

// An "ID" or "ID.OUTPUT" address: `name` is what results are reported under,
// `target` the node of the flat graph that computes it (output empty: every
// output of that node, reported under the node's id).
struct ResolvedOutput {
  std::string name;
  Target target;
};

// The stages of a run over frames that several processes share (`loom
// submit`, MPI): the simulations the requested outputs read, stepped first in
// dependency order; what each frame computes; and the sinks that gather the
// whole range into one file, run after every frame.
struct RunStages {
  std::vector<std::string> simulations;
  std::vector<std::string> per_frame;  // "ID" or "ID.OUTPUT", as --target takes them
  std::vector<std::string> sequences;
};

class LOOM_API GraphView {
 public:
  // `graph` must have passed validate_graph with `registry`; both outlive the view.
  GraphView(const Graph& graph, const Registry& registry);
  ~GraphView();
  GraphView(const GraphView&) = delete;
  GraphView& operator=(const GraphView&) = delete;

  const Graph& graph() const { return graph_; }

  // A node of the flat graph or a group instance's path.
  bool has(const std::string& id) const;
  // Throws Error naming the nearest ids for one that is neither.
  NodeKind kind(const std::string& id) const;
  // The node's declaration: its plugin's or Python module's type, Repeat's
  // (count and the body's interface), or a group instance's interface as a
  // node type (inputs as declared, outputs typed by the inner outputs).
  const NodeType& type(const std::string& id) const;

  // The nodes of the flat graph inside group instance `instance` (at any
  // depth of its inner groups), sorted; empty for any other id. What a
  // front end sums to show an instance's status.
  std::vector<std::string> inner_nodes(const std::string& instance) const;

  // The sinks of the graph (a Repeat whose body writes files is one), by id.
  std::vector<std::string> sinks() const;

  // "ID.INPUT" as --set, --sweep and Python's set= take it. Throws Error
  // saying what the address names instead (no such node, no such input).
  ResolvedInput input(const std::string& address) const;
  // "ID" or "ID.OUTPUT" as --target, --record and Python targets take it:
  // several for a group instance named whole (one per interface output) and
  // for a node inside a group or a Repeat node named whole (one per output).
  // Throws Error for an address that names nothing.
  std::vector<ResolvedOutput> outputs(const std::string& address) const;
  std::vector<ResolvedOutput> outputs(const std::vector<Target>& targets) const;

  // The flat nodes `targets` (every sink when empty) read through links,
  // each after every node it reads.
  std::vector<std::string> upstream(const std::vector<std::string>& targets) const;
  // The stages of a run of `targets` (every sink when empty) over frames.
  RunStages stages(const std::vector<std::string>& targets) const;

  // The files the graph is made from (its own file, the group files it
  // uses, the modules of its Python node types) and the input files its
  // nodes read by literal path, absolute.
  std::vector<std::filesystem::path> files() const;

 private:
  const Graph& graph_;
  const Registry& registry_;
  std::map<std::string, std::unique_ptr<NodeType>> instance_types_;
};

// Repeat's declaration for a body group declared as `body` (a group's node
// type: GraphView::type of an instance, group_node_type of a file): "count"
// (Int >= 0) first, then the body's inputs but an Int or Float "iteration"
// (Repeat feeds it), and the body's outputs. Front ends that draw a Repeat
// node before its graph validates ask this, as the engine does. Throws Error
// when the body declares an input "count".
LOOM_API NodeType repeat_declaration(const NodeType& body, const std::string& body_name);

// Outputs as an evaluation of view.graph() reports them (EvalResult::outputs,
// or one frame of outputs_per_frame), each under its "ID.OUTPUT" name: a
// node named whole gives one per output.
LOOM_API std::vector<std::pair<std::string, Value>> named_outputs(
    const GraphView& view, const std::map<std::string, std::vector<Value>>& outputs);
// Each requested output's values, one per frame evaluated ("--target over
// frames is the list of its values"), under its "ID.OUTPUT" name.
LOOM_API std::vector<std::pair<std::string, std::vector<Value>>> named_outputs_per_frame(const GraphView& view,
                                                                                         const EvalResult& result);

}  // namespace loom
