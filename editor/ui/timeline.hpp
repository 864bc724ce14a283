// The time slider, under the canvas and viewer when the graph has a time
// range: the current frame, scrub by dragging on the bar, step -1/+1, play
// and pause at the graph's fps, loop, and the frames whose result of the
// viewed node the session keeps marked on the bar (the controller asks
// Session::cached_frames after every evaluation).
//
// The frame is the document's (GraphDocument::frame, kept in the graph's
// "ui" field); EditorApp evaluates the graph at it, in the background like
// every other evaluation.
#pragma once

#include <vector>

#include <imgui.h>

#include "editor_state.hpp"
#include "model/playback.hpp"

namespace loom::editor {

class Timeline {
 public:
  static constexpr float kHeight = 58;  // the pane's height in pixels

  // Draws into the current window. `shown` is whether the viewer shows the
  // current frame's evaluation (playback waits for it).
  void draw(EditorState& state, bool shown);
  // Moves on when playing and the frame is shown (call once per UI frame).
  void tick(EditorState& state, bool shown);

  Playback& playback() { return playback_; }
  // The marked frames of the newest evaluation, if it is of the viewed node.
  std::vector<int> marks(const EditorState& state) const;
  // The bar on screen (after a draw), and where a frame sits on it.
  ImVec2 bar_min() const { return bar_min_; }
  ImVec2 bar_max() const { return bar_max_; }
  ImVec2 frame_position(int frame) const;

 private:
  int frame_at(float x) const;
  Playback playback_;
  TimeRange range_;
  ImVec2 bar_min_{0, 0}, bar_max_{0, 0};
};

}  // namespace loom::editor
