// Internal: the one rule that binds a value to a node input. A literal from
// the graph file or a default, and a value arriving over a link, pass the same
// steps: convert (literals only), check against the declaration (range, enum
// choices), and for a file input expand {frame} (output files) and resolve the
// path (input files against the graph's folder, output files under --out).
#pragma once

#include <filesystem>
#include <string>

#include "loom/node.hpp"

namespace loom::detail {

// Where a bound value is used: what its paths resolve against.
struct BindingPlace {
  std::filesystem::path graph_dir;
  std::filesystem::path output_dir;
  bool allow_outside_output = false;
  int frame = 1;
};

// A graph file's literal as a value of the input's type. Throws Error saying
// what was expected (the caller adds the file and JSON pointer).
Value convert_literal(const InputSpec& spec, const json& literal);

// Throws Error, without naming the input, when a numeric component lies
// outside [min, max] (NaN included) or a string is not one of the choices.
// Types without numbers or choices pass.
void check_declared(const InputSpec& spec, const Value& value);

// Converted and checked: what validation asks of every literal.
Value literal_value(const InputSpec& spec, const json& literal);

// The binding rule for a value of the input's type, literal or linked:
// checked, then for a file input the path expanded and resolved. Throws Error
// naming the input.
Value bind_value(const InputSpec& spec, const Value& value, const BindingPlace& place);

// A path given to an output file, resolved under `output_dir`: refused when
// it is empty or holds NUL or other control characters, and, unless
// `allow_outside`, when it is absolute or its ".." leave the folder. Throws
// Error without naming the input.
std::string resolve_output_path(const std::string& path, const std::filesystem::path& output_dir,
                                bool allow_outside);

// A path given to an input file, relative to the graph's folder; refused when
// it is empty or holds control characters.
std::string resolve_input_path(const std::string& path, const std::filesystem::path& graph_dir);

}  // namespace loom::detail
