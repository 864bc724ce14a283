// The selected node's inputs, with widgets generated from its declaration:
// sliders within declared ranges, combos for enums, colour pickers, vector
// fields, a file picker for file inputs, JSON text for lists and other
// literals, a "linked" indicator and the input descriptions as tooltips.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <utility>

#include <imgui.h>

#include "editor_state.hpp"
#include "file_dialog.hpp"

namespace loom::editor {

class PropertyPanel {
 public:
  void draw(EditorState& state, FileDialog& files);
  // Where the widget of an input of the selected node was drawn last frame
  // (screen pixels, min and max), for scripted tests.
  std::optional<std::pair<ImVec2, ImVec2>> widget_rect(const std::string& input) const {
    auto it = rects_.find(input);
    if (it == rects_.end()) return std::nullopt;
    return it->second;
  }

 private:
  void draw_input(EditorState& state, FileDialog& files, const std::string& id, const InputSpec& spec);
  std::map<std::string, std::string> text_;   // JSON text being edited, by "id.input"
  std::map<std::string, std::string> error_;  // why that text was not applied
  std::map<std::string, std::pair<ImVec2, ImVec2>> rects_;
  std::string rects_node_;
};

}  // namespace loom::editor
