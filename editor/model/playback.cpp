#include "playback.hpp"

#include <algorithm>

namespace loom::editor {

void Playback::play(double now, const TimeRange& range, int& frame) {
  if (frame >= range.end && !loop_) frame = range.start;
  playing_ = true;
  last_ = now;
}

std::optional<int> Playback::tick(double now, bool ready, const TimeRange& range, int frame) {
  const double period = 1.0 / range.fps;
  if (!playing_ || !ready || now - last_ < period) return std::nullopt;
  // On time: keep the cadence (the UI's frames do not divide 1/fps); late
  // (the graph is slower than fps): from now on.
  last_ = now - last_ < 2 * period ? last_ + period : now;
  if (frame < range.end) return std::max(frame + 1, range.start);
  if (loop_ && range.end > range.start) return range.start;
  playing_ = false;
  return std::nullopt;
}

int Playback::step(int frame, int by, const TimeRange& range) {
  playing_ = false;
  return std::clamp(frame + by, range.start, range.end);
}

}  // namespace loom::editor
