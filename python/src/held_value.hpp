// In-memory values as node inputs. An input given a NumPy array or a
// loom.Mesh cannot be written into a graph file, so a run links it from a
// hidden node of type "python.HeldValue" whose one literal input is the
// value's content hash: re-running with the same array is a cache hit, a
// changed array recomputes what depends on it.
#pragma once

#include <cstdint>
#include <string>

#include "loom/graph.hpp"

namespace loom::python {

NodeType held_value_type();

// A value given from Python with its content hash, computed once when given.
struct Held {
  Value value;
  std::string key;
};
// Converts and hashes; throws loom::Error like from_python.
Held hold(const Value& value);

// Keeps the values reachable by their keys while a run that links them is alive.
class HeldValues {
 public:
  HeldValues() = default;
  HeldValues(const HeldValues&) = delete;
  HeldValues& operator=(const HeldValues&) = delete;
  ~HeldValues();
  // Adds a hidden node feeding `node`'s `input` with `value` to the graph.
  void link(Graph& graph, const std::string& node, const std::string& input, const Held& held);

 private:
  std::vector<std::string> keys_;
};


}  // namespace loom::python
