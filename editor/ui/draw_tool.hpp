// The DrawShapes tool (the MiniDraw application): choose line, rectangle,
// ellipse, polygon or freehand, a stroke colour, width and optional fill, and
// draw on the image; each finished figure is appended to the node's "figures"
// input (one undo step), in the format DrawShapes reads.
#pragma once

#include <string>
#include <vector>

#include "editor_state.hpp"
#include "image_viewer.hpp"

namespace loom::editor {

class DrawTool {
 public:
  enum class Shape { line, rectangle, ellipse, polygon, freehand };
  static bool applies(const EditorState& state, const std::string& id);
  void toolbar();
  void draw(EditorState& state, const std::string& id, const ImageView& view);

  // What the toolbar sets (public for scripted tests).
  Shape shape = Shape::rectangle;
  float stroke[4] = {0.1f, 0.1f, 0.1f, 1};
  float fill_color[4] = {0.9f, 0.3f, 0.25f, 1};
  bool fill = true;
  float width = 3;

 private:
  json figure(const std::vector<ImVec2>& points) const;
  void preview(const ImageView& view) const;
  std::vector<ImVec2> draft_;  // image pixels
  bool dragging_ = false;
};

}  // namespace loom::editor
