// The JSON of grouping, ungrouping and promoting, as pure functions of a
// level's "nodes" (the top graph's or an inline group's), in the agreed
// composition format (docs/graph-format.md): GraphDocument wraps each in one
// undo step.
#pragma once

#include <functional>
#include <map>
#include <set>
#include <string>

#include "loom/node.hpp"

namespace loom::editor {

// The type of a node of the level, by id (null when unknown).
using NodeTypeOf = std::function<const NodeType*(const std::string& id)>;

struct Grouping {
  // {"inputs", "outputs", "nodes"}: every link entering the selection is an
  // interface input ("to" its inner inputs, one per outer output), every
  // inner output read outside is an interface output; the inner inputs fed
  // by the interface are left unset.
  json definition;
  // The group node's "inputs": the outer outputs feeding the interface.
  json instance_inputs;
  // Outer consumers to rewire: (node, input) -> the interface output's name.
  std::map<std::pair<std::string, std::string>, std::string> consumers;
};
Grouping make_grouping(const json& nodes, const std::set<std::string>& chosen, const NodeTypeOf& type_of_node);

struct Ungrouping {
  json nodes;  // the inner nodes under their new ids, wired to the parent
  std::map<std::string, std::string> renamed;  // inner id -> new id
  std::map<std::string, std::string> outputs;  // interface output -> "NEW.OUTPUT"
};
// Group node `id` (its JSON `instance`, at `at`) dissolved into a parent
// whose ids `taken` says are used: inner ids become ID_INNER (made unique),
// interface inputs become the group node's links or literals (else the
// interface's default) on the inner inputs they feed.
Ungrouping dissolve_group(const std::string& id, const json& instance, const json& definition,
                          const std::function<bool(const std::string&)>& taken);

// Adds to `group` (an inline definition or a group file's top) an interface
// input feeding node.input, declared as `declared` (type, range, choices,
// description) with the inner literal, when set, as its default so nothing
// evaluated changes; the inner literal is removed. Returns its name.
std::string promote_input(json& group, const std::string& node, const std::string& input,
                          const InputSpec& declared);

// The interface input of `group` bound to node.input, or "".
std::string interface_input_of(const json& group, const std::string& node, const std::string& input);

// `base`, or base2, base3, ... : the first that `taken` refuses.
std::string unique_name(const std::string& base, const std::function<bool(const std::string&)>& taken);

}  // namespace loom::editor
