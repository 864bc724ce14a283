// The node canvas, drawn with ImDrawList: boxes with typed, coloured sockets,
// links as Bézier curves, pan (right or middle drag) and zoom (wheel), box
// selection, link drags refused with a tooltip, an "add node" menu (right
// click or Tab) and the node's status from the last evaluation.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <imgui.h>

#include "editor_state.hpp"

namespace loom::editor {

class Canvas {
 public:
  // Draws into the current window, filling the remaining content region.
  void draw(EditorState& state);

  // Geometry in screen pixels (valid after the first draw), for the tests and
  // the tools that point at nodes.
  ImVec2 to_screen(CanvasPoint p) const;
  CanvasPoint to_canvas(ImVec2 screen) const;
  ImVec2 node_header(const EditorState& state, const std::string& id) const;
  std::optional<ImVec2> input_socket(const EditorState& state, const std::string& id,
                                     const std::string& input) const;
  std::optional<ImVec2> output_socket(const EditorState& state, const std::string& id,
                                      const std::string& output) const;
  // Pans and zooms so every node is visible.
  void frame_all(const EditorState& state);
  float zoom() const { return zoom_; }
  // The node drawn at a screen point (the topmost), or empty.
  std::string hit_node(const EditorState& state, ImVec2 screen) const;
  const std::string& refusal() const { return refusal_; }  // the last refused link's reason
  bool menu_open() const { return menu_open_; }  // the add-node search, last frame
  // Where a new node of this type goes: the free spot nearest to `at`.
  CanvasPoint free_place(const EditorState& state, CanvasPoint at, const std::string& type) const;

 private:
  struct Box {
    float width, height;
  };
  Box box(const EditorState& state, const std::string& id) const;
  void draw_links(EditorState& state, ImDrawList* draw);
  struct NodeLook;
  void draw_node(EditorState& state, ImDrawList* draw, const std::string& id);
  void draw_node_box(EditorState& state, ImDrawList* draw, const std::string& id, const NodeLook& look);
  void draw_input_row(EditorState& state, ImDrawList* draw, const std::string& id, const InputSpec& in,
                      const NodeLook& look, float y);
  void draw_node_footer(EditorState& state, ImDrawList* draw, const std::string& id, const NodeLook& look, float y);
  void draw_value(ImDrawList* draw, ImFont* face, float font, ImVec2 row, const InputSpec& in,
                  const json& literal) const;
  void draw_group_input(ImDrawList* draw, ImFont* face, float font, ImVec2 row, const std::string& name) const;
  void handle_mouse(EditorState& state);
  void zoom_at(ImVec2 mouse);
  void explain_hovered(EditorState& state, ImVec2 mouse);
  void begin_gesture(EditorState& state, ImVec2 mouse);
  void begin_left_press(EditorState& state, ImVec2 mouse);
  void continue_move(EditorState& state, ImVec2 mouse);
  void continue_link(EditorState& state, ImVec2 mouse);
  void continue_box(EditorState& state, ImVec2 mouse);
  void continue_pan(ImVec2 mouse);
  void handle_keys(EditorState& state);
  void add_node_menu(EditorState& state);
  struct SocketHit {
    std::string node, name;
    bool output = false;
  };
  std::optional<SocketHit> hit_socket(const EditorState& state, ImVec2 screen) const;

  ImVec2 origin_{0, 0}, size_{0, 0};  // the canvas region on screen
  ImVec2 pan_{0, 0};
  float zoom_ = 1;
  bool framed_once_ = false;

  enum class Gesture { none, move, link, box, pan };
  Gesture gesture_ = Gesture::none;
  ImVec2 press_{0, 0};
  CanvasPoint drag_last_{};
  SocketHit link_from_;
  std::string refusal_;
  double refusal_until_ = 0;
  CanvasPoint menu_at_{};
  std::string menu_filter_;
  bool menu_focus_ = false, menu_open_ = false;
};

// Replaces every selected group node by its inner nodes (one undo step each).
void ungroup_selection(EditorState& state);

// The colour of a type's sockets and links.
ImU32 type_color(const TypeInfo& type);

}  // namespace loom::editor
