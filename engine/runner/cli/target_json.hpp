// What `loom run --target X --json` prints: the requested outputs as one JSON
// object, each value in full.
#pragma once

#include <string>

#include "loom/evaluator.hpp"
#include "loom/registry.hpp"

namespace loom::runner {

// A value as --json and --record give it: its JSON form (numbers at full
// precision, lists, JSON), or {"type": …, "summary": …} for any other.
json value_json(const Value& value);

// {"ID.OUTPUT": value, ...}: a value with a JSON form (numbers at full
// precision, lists, JSON) as itself, any other as {"type": …, "summary": …};
// an output kept at several frames as the list of its values in frame order.
std::string target_json(const Graph& graph, const Registry& registry, const EvalResult& result);

}  // namespace loom::runner
