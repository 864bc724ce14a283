// An input's value in the graph JSON as a link: {"from": "ID.OUTPUT"}, read
// by the engine's one parser of "ID.OUTPUT" (loom::parse_link).
#pragma once

#include <optional>

#include "loom/graph.hpp"

namespace loom::editor {

inline std::optional<Link> input_link(const json& value) {
  if (!value.is_object() || !value.contains("from") || !value["from"].is_string()) return std::nullopt;
  return parse_link(value["from"].get<std::string>());
}

}  // namespace loom::editor
