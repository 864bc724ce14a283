// Playing a graph's frames: play/pause at the graph's fps, step, loop. No
// ImGui here: the time slider draws it, the tests drive it with a clock.
//
// Playback never waits for the engine: it moves on only when the current
// frame's evaluation has been shown (`ready`) and a frame time (1/fps) has
// passed since the last move, so it drops to the rate the graph computes.
#pragma once

#include <optional>

#include "loom/graph.hpp"

namespace loom::editor {

class Playback {
 public:
  bool playing() const { return playing_; }
  bool loop() const { return loop_; }
  void set_loop(bool loop) { loop_ = loop; }
  // Playing from the end of the range without looping starts over.
  void play(double now, const TimeRange& range, int& frame);
  void pause() { playing_ = false; }
  // The frame to show next, if it is time to move on; stops at the end
  // unless looping.
  std::optional<int> tick(double now, bool ready, const TimeRange& range, int frame);
  // One frame back or on, within the range (stepping pauses).
  int step(int frame, int by, const TimeRange& range);

 private:
  bool playing_ = false, loop_ = true;
  double last_ = 0;  // when the shown frame was moved to
};

}  // namespace loom::editor
