// Host API. One node's body run once on given values, outside any graph: the
// runner's --preview writes a partial image through SaveImage this way, and
// the editor's viewer shows an image through DisplayView. Nothing is cached,
// nothing is planned; the node must not be a simulation or time-dependent.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "loom/export.hpp"
#include "loom/node.hpp"

namespace loom {

struct NodeCall {
  std::map<std::string, Value> values;  // inputs given as values (an image)
  json literals = json::object();       // inputs given as graph-file literals ({"view": "Raw"})
  std::string id = "call";              // the node's id in its messages
  std::filesystem::path dir = ".";      // graph and output folder for relative paths
  std::function<void(bool warning, const std::string& text)> report;  // its messages; none: dropped
};

// Runs `type` on `call`'s inputs, every other input at its default, and
// returns its outputs in declaration order. Throws loom::Error: the node's
// own, a literal its declaration refuses (checked as a graph file's is), an
// input neither given nor defaulted, or a name the node does not have.
LOOM_API std::vector<Value> call_node(const NodeType& type, const NodeCall& call);

}  // namespace loom
