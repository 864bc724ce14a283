// Which widget edits an input in the properties panel, chosen once from its
// declaration by a table of types (not by a chain of type comparisons in the
// panel): numbers within a declared range get sliders, wider or open ranges
// drag fields, enums a combo, file paths a text field with a file picker.
#pragma once

#include "loom/node.hpp"

namespace loom::editor {

enum class InputWidget {
  link_only,       // no literal form (Image, Mesh, ...): link an output to it
  checkbox,        // Bool
  int_slider,      // Int within a declared range of at most kSliderSpan
  int_drag,        // Int, open or wide range
  number_slider,   // Float (edited as double) within a declared range
  number_drag,     // Float, open or wide range
  choice,          // Enum
  text,            // String
  file,            // String naming an input or output file: text and "..."
  color,           // Color
  int_vector,      // Vec2i, Vec3i
  number_vector,   // Vec2, Vec3 (edited as doubles)
  json_text,       // lists, point pairs, JSON: text, applied when valid JSON
};

// A range wider than this is dragged, not slid (a slider's pixel would step
// by more than the user can aim).
constexpr double kSliderSpan = 10000;

InputWidget widget_for(const InputSpec& spec);
// Components of a vector widget (2 or 3), 0 for the others.
int vector_size(const InputSpec& spec);

}  // namespace loom::editor
