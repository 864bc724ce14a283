// The PoissonBlend tool (the seamless-cloning assignment's application):
// draw the region as a rectangle or a polygon on the source image, then drag
// it over the target. Dragging writes the node's "offset" input, one undo
// step per drag; while the mouse is held the running solve finishes rather
// than being cancelled, so the blend keeps updating (the node's multigrid
// hierarchy is cached per region, so a new offset costs one warm solve).
#pragma once

#include <string>
#include <vector>

#include "editor_state.hpp"
#include "image_viewer.hpp"

namespace loom::editor {

class PoissonTool {
 public:
  enum class Mode { move, rectangle, polygon };
  static bool applies(const EditorState& state, const std::string& id);
  // The mode buttons; returns true when the source is to be shown (drawing).
  bool toolbar();
  void set_mode(Mode mode) { mode_ = mode; draft_.clear(); }
  Mode mode() const { return mode_; }
  // `view` shows the source while drawing, the blend otherwise.
  void draw(EditorState& state, const std::string& id, const ImageView& view);

 private:
  void draw_region(EditorState& state, const std::string& id, const ImageView& view);
  void move_region(EditorState& state, const std::string& id, const ImageView& view);
  Mode mode_ = Mode::move;
  bool dragging_ = false;
  ImVec2 press_{0, 0};
  int offset_at_press_[2] = {0, 0};
  std::vector<ImVec2> draft_;  // polygon vertices or the rectangle's corners (image pixels)
};

}  // namespace loom::editor
