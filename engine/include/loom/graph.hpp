// Graph files: parsing, validation against a registry, and writing back.
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
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "loom/registry.hpp"

namespace loom {

constexpr int kGraphFormatVersion = 1;
// Graph files and --set values nested deeper than this are refused when
// parsed (a deeper document would exhaust the stack of any recursive walk).
constexpr std::size_t kMaxJsonDepth = 256;

struct Link {
  std::string node;
  std::string output;
};

// The one parser of the names written "ID.MEMBER" (links "ID.OUTPUT",
// targets, --set's "ID.INPUT"): the member after the last '.', the node before
// it; nullopt when either is empty or there is no '.'. Node ids and input and
// output names hold no '.', so the split is unambiguous.
LOOM_API std::optional<Link> parse_link(std::string_view text);

struct InputBinding {
  std::optional<Link> link;  // set: linked; unset: literal
  json literal;
  std::string set_by = {};  // the --set assignment that gave this value, for messages; empty: the file
};

struct GraphNode {
  std::string id;
  std::string type;
  std::map<std::string, InputBinding> inputs;
  json ui;  // editor layout, kept as is
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
  std::uint64_t seed = 0;
  std::optional<TimeRange> time;
  std::map<std::string, GraphNode> nodes;  // by id, sorted
  json ui;  // editor state (e.g. the current frame), kept as is

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

// Applies `--set ID.INPUT=JSON`; a value that is not valid JSON is taken as a
// string. Throws GraphError for an unknown node. `time.start`, `time.end` and
// `time.fps` set the graph's time (unless a node is named "time").
LOOM_API void set_input(Graph& graph, const std::string& assignment);

LOOM_API json graph_to_json(const Graph& graph);

// Whether an output of type `from` may feed an input of type `to`: the same
// stored C++ type (Enum takes String), or either side Any (checked when the
// value arrives). The one rule for validation and the editor's link drag.
LOOM_API bool link_compatible(const TypeInfo& from, const TypeInfo& to);

// The node types a graph uses, for loading only the plugins it needs.
LOOM_API std::vector<std::string> node_types_used(const Graph& graph);

}  // namespace loom
