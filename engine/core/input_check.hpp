// Internal: the checks every value arriving at a node input passes, linked or
// literal, against what the input declares (range, enum choices), and the
// rules for file paths in inputs.
#pragma once

#include <filesystem>
#include <string>

#include "loom/node.hpp"

namespace loom::detail {

// Throws Error naming the input and its declared range or choices when a
// numeric component lies outside [min, max] (NaN included) or a string is not
// one of the choices. Types without numbers or choices pass unchanged.
void check_input_value(const InputSpec& spec, const Value& value);

// A path given to an output_file input, resolved under `output_dir`: refused
// when it is empty or holds NUL or other control characters, and, unless
// `allow_outside`, when it is absolute or its ".." leave the folder.
std::string resolve_output_path(const std::string& path, const std::filesystem::path& output_dir,
                                bool allow_outside);

// A path given to an input_file input, relative to the graph's folder;
// refused when it is empty or holds control characters.
std::string resolve_input_path(const std::string& path, const std::filesystem::path& graph_dir);

// Resolves a linked or literal value for an input with a file role (a String)
// by the rules above; other roles pass unchanged.
Value resolve_path_value(const InputSpec& spec, const Value& value, const std::filesystem::path& graph_dir,
                         const std::filesystem::path& output_dir, bool allow_outside);

}  // namespace loom::detail
