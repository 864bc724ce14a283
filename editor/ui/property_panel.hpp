// The selected node's inputs, with widgets generated from its declaration
// (model/input_widget.hpp chooses them): sliders within declared ranges, drag
// fields, combos for enums, colour pickers, vector fields, a file picker for
// file inputs, JSON text for lists and other literals, a "linked" indicator
// and the input descriptions as tooltips. Numbers are edited as doubles, so
// a value survives a save exactly as typed.
//
// Laid out as a table (name | widget | reset), the name column as wide as the
// longest name: no label or button is cut off; a pane narrower than the table
// scrolls sideways instead.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <utility>

#include <imgui.h>

#include "editor_state.hpp"
#include "file_dialog.hpp"
#include "model/input_widget.hpp"

namespace loom::editor {

class PropertyPanel {
 public:
  void draw(EditorState& state, FileDialog& files);
  using Rect = std::pair<ImVec2, ImVec2>;  // screen pixels, min and max
  // Where the widget of an input of the selected node was drawn last frame,
  // for scripted tests.
  std::optional<Rect> widget_rect(const std::string& input) const { return find(widgets_, input); }
  // Where its name and its "reset" or "unlink" button were drawn (the button: none when not shown).
  std::optional<Rect> label_rect(const std::string& input) const { return find(labels_, input); }
  std::optional<Rect> button_rect(const std::string& input) const { return find(buttons_, input); }
  // The pane's visible region last frame.
  Rect visible_rect() const { return visible_; }
  // Where the selected group node's "enter group" button was drawn last frame.
  std::optional<Rect> enter_button_rect() const { return enter_button_; }

 private:
  static std::optional<Rect> find(const std::map<std::string, Rect>& rects, const std::string& input) {
    auto it = rects.find(input);
    if (it == rects.end()) return std::nullopt;
    return it->second;
  }
  void draw_input(EditorState& state, FileDialog& files, const std::string& id, const InputSpec& spec);
  bool group_actions(EditorState& state, const std::string& id);
  void promote_menu(EditorState& state, const std::string& id, const InputSpec& spec);
  void draw_instance_input(EditorState& state, FileDialog& files, const InputSpec& spec, const std::string& name);
  bool edit_literal(EditorState& state, FileDialog& files, const std::string& id, const InputSpec& spec,
                    const json& value, json& next);
  bool edit_json_text(const std::string& key, const json& value, json& next);
  std::map<std::string, std::string> text_;   // JSON text being edited, by "id.input"
  std::map<std::string, std::string> error_;  // why that text was not applied
  std::map<std::string, Rect> widgets_, labels_, buttons_;
  Rect visible_{};
  std::optional<Rect> enter_button_;
  std::string rects_node_;
};

}  // namespace loom::editor
