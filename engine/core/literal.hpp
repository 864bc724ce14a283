// Internal: turning a graph file's literal into a Value for an input.
#pragma once

#include "loom/node.hpp"

namespace loom::detail {

// Converts and checks (type, enum choice, range). Throws Error with what was
// expected; the caller adds file and pointer.
Value literal_value(const InputSpec& spec, const json& literal);

std::string pointer_escape(const std::string& token);

}  // namespace loom::detail
