// The ImageWarp tool on the image viewer (the IDW/RBF assignment's
// application): click and drag on the image to add a pair p -> q, drag either
// end of a pair, right-click an end to delete its pair. Every change writes
// the node's "pairs" input (an ordinary literal, one undo step per drag), so
// the warp re-evaluates live and the session is a runnable graph file.
#pragma once

#include <string>

#include "editor_state.hpp"
#include "image_viewer.hpp"

namespace loom::editor {

class WarpTool {
 public:
  // Whether node `id` takes pairs the tool can edit (a literal "pairs" input
  // of a PointPairs type, not linked).
  static bool applies(const EditorState& state, const std::string& id);
  void draw(EditorState& state, const std::string& id, const ImageView& view);

 private:
  int dragging_ = -1;      // the pair being dragged
  bool dragging_q_ = true;  // which end
};

}  // namespace loom::editor
