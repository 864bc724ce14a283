// Author and host API. An input's declaration written as JSON, the one
// vocabulary of group interfaces (docs/graph-format.md, "Groups"),
// `loom nodes --json` and Python's loom.In: type, default, min, max, choices,
// optional, description. The one reader and the one writer of it.
#pragma once

#include <string>
#include <vector>

#include "loom/node.hpp"

namespace loom {

enum class DeclarationReading {
  strict,   // every key checked; throws Error naming the key (graph files, Python)
  lenient,  // what can be read is kept, an unknown type is Any (the editor, mid-edit)
};

// The names of the registered value types, sorted (value.cpp).
LOOM_API std::vector<std::string> type_names();

// The type a declaration names; throws Error with the nearest names when no
// type is registered under it (an input's or an output's "type").
LOOM_API const TypeInfo& declared_type(const std::string& name);

LOOM_API InputSpec input_spec_from_json(const std::string& name, const json& declaration,
                                        DeclarationReading reading = DeclarationReading::strict);

// The declaration's keys, those at their defaults left out (no null default,
// no "optional": false, no empty description or choices).
LOOM_API json input_spec_to_json(const InputSpec& spec);

// A literal for the input, converted and checked against the declaration
// (type, range, choices) as validation checks a graph file's. Throws Error
// without naming the input.
LOOM_API void check_literal(const InputSpec& spec, const json& literal);

}  // namespace loom
