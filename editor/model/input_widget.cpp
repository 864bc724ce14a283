#include "input_widget.hpp"

#include <utility>
#include <vector>

#include "loom/builtin_types.hpp"

namespace loom::editor {

namespace {

struct TypeWidget {
  const TypeInfo* type;
  InputWidget widget;
  int components;
};

// The types with a widget of their own; any other literal type is JSON text.
const std::vector<TypeWidget>& type_widgets() {
  static const std::vector<TypeWidget> table = {
      {&type_of<bool>(), InputWidget::checkbox, 0},       {&type_of<int>(), InputWidget::int_drag, 0},
      {&type_of<double>(), InputWidget::number_drag, 0},  {&enum_type(), InputWidget::choice, 0},
      {&type_of<std::string>(), InputWidget::text, 0},    {&type_of<Color>(), InputWidget::color, 0},
      {&type_of<Vec2i>(), InputWidget::int_vector, 2},    {&type_of<Vec3i>(), InputWidget::int_vector, 3},
      {&type_of<Vec2>(), InputWidget::number_vector, 2},  {&type_of<Vec3>(), InputWidget::number_vector, 3},
  };
  return table;
}

const TypeWidget* find(const TypeInfo* type) {
  for (const TypeWidget& t : type_widgets())
    if (t.type == type) return &t;
  return nullptr;
}

}  // namespace

InputWidget widget_for(const InputSpec& spec) {
  if (!spec.type || !spec.type->literal()) return InputWidget::link_only;
  const TypeWidget* t = find(spec.type);
  if (!t) return InputWidget::json_text;
  const bool slidable = spec.min && spec.max && *spec.max - *spec.min <= kSliderSpan;
  switch (t->widget) {
    case InputWidget::int_drag: return slidable ? InputWidget::int_slider : InputWidget::int_drag;
    case InputWidget::number_drag: return slidable ? InputWidget::number_slider : InputWidget::number_drag;
    case InputWidget::text: return spec.role == InputRole::value ? InputWidget::text : InputWidget::file;
    default: return t->widget;
  }
}

int vector_size(const InputSpec& spec) {
  const TypeWidget* t = find(spec.type);
  return t ? t->components : 0;
}

}  // namespace loom::editor
