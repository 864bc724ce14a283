// Viewers for values that are not images: number lists as plots (e.g. an
// energy per iteration), JSON reports as trees, anything else as its JSON or
// its one-line summary.
#pragma once

#include "loom/builtin_types.hpp"

namespace loom::editor {

void draw_value(const Value& value);
void draw_plot(const std::vector<double>& values);
void draw_json_tree(const json& value);

}  // namespace loom::editor
