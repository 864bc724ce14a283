// Host API. Graph files: parsing, validation against a registry, and writing back.
//
//   {"loom": 1, "seed": 7, "nodes": {
//     "board": {"type": "Checkerboard", "inputs": {"size": [512, 512]}},
//     "save":  {"type": "SaveImage", "inputs": {"image": {"from": "board.image"},
//                                               "path": "board.png"}}}}
//
// Every error names the file, the JSON pointer and what was expected.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "loom/registry.hpp"

namespace loom {

// Files without groups are written as version 1; a file that uses groups
// (docs/graph-format.md, "Groups") says "loom": 2. Version 1 is a subset of 2.
constexpr int kGraphFormatVersion = 1;
constexpr int kGroupsFormatVersion = 2;
// Graph files and --set values nested deeper than this are refused when
// parsed (a deeper document would exhaust the stack of any recursive walk).
constexpr std::size_t kMaxJsonDepth = 256;

struct Link {
  std::string node;
  std::string output;
};

// The one parser of the names written "ID.MEMBER" (links "ID.OUTPUT",
// targets, --set's "ID.INPUT"): the member after the last '.', the node before it; nullopt when either is
// empty or there is no '.'. Input and output names hold no '.', so paths of nodes in groups split too
// ("look.render.width"); what an address names is the answer of loom/graph_view.hpp, not of the split.
LOOM_API std::optional<Link> parse_link(std::string_view text);
// The one writer of those names: "NODE.MEMBER".
LOOM_API std::string link_text(std::string_view node, std::string_view member);
inline std::string link_text(const Link& link) { return link_text(link.node, link.output); }

struct InputBinding {
  std::optional<Link> link;  // set: linked; unset: literal
  json literal;
  std::string set_by = {};  // the --set assignment that gave this value, for messages; empty: the file
};

// Where something was written: its file (empty: the graph's own file) and
// its JSON pointer there. Nodes of a group keep the place of their definition,
// so errors point into the group's file.
struct SourcePlace {
  std::string file;
  std::string pointer;
};

struct RepeatBody;  // a Repeat node's body (engine/core/repeat.hpp)

struct GraphNode {
  std::string id;  // inside a group instance, a path: "look.render"
  std::string type;
  std::map<std::string, InputBinding> inputs;
  json ui;  // editor layout, kept as is
  SourcePlace place = {};  // empty pointer: /nodes/ID of the graph's own file
  // What seeds the node's random numbers (with the graph seed): its own id
  // in the group that wrote it ("render" for "look.render"), so that
  // grouping nodes keeps their random numbers and two instances of a group
  // with equal inputs compute, hash and share the same results.
  std::string seed_name = {};
  std::shared_ptr<const RepeatBody> repeat = {};  // set for a node of type "Repeat"

  const std::string& seed_key() const { return seed_name.empty() ? id : seed_name; }
};

// A group's interface: inputs declared like a C++ node's (type, default,
// min, max, choices, optional, description) and the inner NODE.INPUTs each
// feeds; outputs taken from inner NODE.OUTPUTs. Paths are flat ids.
struct GroupInput {
  json declaration;
  std::vector<Link> to;
  SourcePlace place;  // of the declaration
  // The declaration as the InputSpec a node declares (input_spec_from_json in
  // loom/input_declaration.hpp), read at the first ask, when plugins have
  // registered the value types, and kept: null when invalid, *problem saying why.
  LOOM_API const InputSpec* spec(std::string* problem = nullptr) const;
  std::shared_ptr<struct ReadDeclaration> read = {};  // what spec() keeps
};
struct GroupInterface {
  std::string description;
  std::map<std::string, GroupInput> inputs;
  std::map<std::string, Link> outputs;
  std::map<std::string, SourcePlace> output_places;
};
// A node of a group type, expanded: its inner nodes are in Graph::nodes as
// "PATH.INNER"; this keeps its interface and the values given to it.
struct GroupInstance {
  std::string type;
  SourcePlace place;  // the instance's node
  GroupInterface interface;
  std::map<std::string, InputBinding> given;
};

// Frame numbers, in graph files and in every run, lie within
// [-kMaxFrame, kMaxFrame]: counts and loops over them never overflow an int.
constexpr int kMaxFrame = 1000000000;
// A lazy input (Switch's) is fetched from inside its node's body, so each
// lazy link of a chain nests one evaluation in another on the stack: chains
// longer than this are refused by validation and when evaluated.
constexpr int kMaxLazyChain = 256;

// "time": {"start": 1, "end": 240, "fps": 24}: the frames a run walks by
// default and their rate. A graph without it is one evaluation at frame 1.
struct TimeRange {
  int start = 1;
  int end = 1;  // inclusive, at least start
  double fps = 24;
};

struct Graph {
  std::filesystem::path file;  // for messages and relative input paths
  int version = kGraphFormatVersion;
  std::uint64_t seed = 0;
  std::optional<TimeRange> time;
  std::map<std::string, GraphNode> nodes;  // by id, sorted; groups expanded (flat)
  json ui;  // editor state (e.g. the current frame), kept as is
  // Version 2: the group instances by path, and a group file's own interface.
  std::map<std::string, GroupInstance> instances;
  std::optional<GroupInterface> interface;
  // The group files the graph was expanded from (absolute, each once).
  std::vector<std::filesystem::path> group_files;

  std::filesystem::path dir() const { return file.empty() ? std::filesystem::current_path()
                                                            : file.parent_path(); }
};

struct GraphIssue {
  std::string pointer;  // JSON pointer, e.g. /nodes/warp/inputs/mu
  std::string message;
  std::string source = {};  // where the value came from when not the file (e.g. "--set warp.mu=2")
};

class LOOM_API GraphError : public Error {
 public:
  GraphError(std::string file, std::vector<GraphIssue> issues);
  const std::vector<GraphIssue>& issues() const { return issues_; }
  const std::string& file() const { return file_; }

 private:
  std::string file_;
  std::vector<GraphIssue> issues_;
};

// Structure only (no registry): JSON syntax, the "loom" version, node shapes,
// links written as "ID.OUTPUT". Throws GraphError.
LOOM_API Graph parse_graph(const json& document, const std::filesystem::path& file);
LOOM_API Graph load_graph_file(const std::filesystem::path& file);
// The same for JSON text in memory (the fuzzer, the editor's paste): any
// failure of the JSON itself (syntax, a number beyond double, nesting deeper
// than kMaxJsonDepth) is a GraphError too.
LOOM_API Graph parse_graph_text(std::string_view text, const std::filesystem::path& file);

// Against the registry: unknown types, unknown inputs, links to unknown nodes
// or outputs, type mismatches, missing required inputs, bad enum values,
// out-of-range values, cycles. Throws GraphError listing every issue found.
// `searched` names where node types were looked for, for unknown-type errors;
// `known_types` (PluginLoader::known_node_types) adds the types of plugins not
// loaded to the registry's for "did you mean".
LOOM_API void validate_graph(const Graph& graph, const Registry& registry,
                             const std::string& searched = {},
                             const std::vector<std::string>& known_types = {});

// Where a group type named by a node of `file` is found: a ".json" path
// relative to the file's folder; else NAME.json in the folders of
// LOOM_GRAPH_PATH (':'-separated), then in Loom's shipped graphs/lib. Empty
// when not found.
LOOM_API std::filesystem::path find_group_file(const std::string& type, const std::filesystem::path& file);
// The folders searched for group files by name, in order.
LOOM_API std::vector<std::filesystem::path> graph_search_path();

// The group files found by name: NAME.json in each folder of
// graph_search_path() holding "inputs" or "outputs" (the first of a name wins).
LOOM_API std::vector<std::filesystem::path> library_group_files();
// A group's interface as a node declaration (what `loom nodes` prints): its
// inputs as declared, its outputs with the types of the inner outputs they
// come from. `group` is a loaded group file (Graph::interface set), `plugin`
// says where it came from. Throws Error for an invalid interface.
LOOM_API NodeType group_node_type(const Graph& group, const std::string& name, const std::string& plugin,
                                  const Registry& registry);

// Applies `--set ID.INPUT=JSON`; a value that is not valid JSON is taken as a
// string. Throws GraphError for an unknown node. ID may be a path into a
// group instance (look.render.width), and INPUT an instance's interface
// input (look.width). `time.start`, `time.end` and
// `time.fps` set the graph's time (unless a node is named "time").
LOOM_API void set_input(Graph& graph, const std::string& assignment);

// The graph as a version 1 document. A graph with groups, Repeat or a group
// file's interface cannot be written back from its expanded form: throws
// Error (write the document it was loaded from; `loom submit` copies it,
// farm/bundle.hpp).
LOOM_API json graph_to_json(const Graph& graph);

// Whether an output of type `from` may feed an input of type `to`: the same
// stored C++ type (Enum takes String), or either side Any (checked when the
// value arrives). The one rule for validation and the editor's link drag.
LOOM_API bool link_compatible(const TypeInfo& from, const TypeInfo& to);

// The node types a graph uses, for loading only the plugins it needs.
LOOM_API std::vector<std::string> node_types_used(const Graph& graph);

}  // namespace loom
