#include "timeline.hpp"

#include <algorithm>
#include <cmath>

#include <GLFW/glfw3.h>

namespace loom::editor {

std::vector<int> Timeline::marks(const EditorState& state) const {
  if (!state.eval || state.eval->frames_of != state.engine_id(state.viewed)) return {};
  return state.eval->cached_frames;
}

ImVec2 Timeline::frame_position(int frame) const {
  const float span = float(std::max(range_.end - range_.start, 1));
  const float t = float(frame - range_.start) / span;
  return {bar_min_.x + t * (bar_max_.x - bar_min_.x), (bar_min_.y + bar_max_.y) * 0.5f};
}

int Timeline::frame_at(float x) const {
  const float t = (x - bar_min_.x) / std::max(bar_max_.x - bar_min_.x, 1.0f);
  const int f = range_.start + int(std::lround(t * float(range_.end - range_.start)));
  return std::clamp(f, range_.start, range_.end);
}

void Timeline::tick(EditorState& state, bool shown) {
  const auto range = state.doc.time_range();
  if (!range) {
    playback_.pause();
    return;
  }
  if (auto next = playback_.tick(glfwGetTime(), shown, *range, state.doc.frame())) state.doc.set_frame(*next);
}

void Timeline::draw(EditorState& state, bool shown) {
  const auto range = state.doc.time_range();
  if (!range) return;
  range_ = *range;
  GraphDocument& doc = state.doc;
  int frame = doc.frame();

  // Transport: first, back, play/pause, on, last, loop.
  if (ImGui::Button("|<")) frame = playback_.step(range_.start, 0, range_);
  ImGui::SameLine();
  if (ImGui::Button("<")) frame = playback_.step(frame, -1, range_);
  ImGui::SameLine();
  if (ImGui::Button(playback_.playing() ? "pause" : "play ", ImVec2(52, 0))) {
    if (playback_.playing())
      playback_.pause();
    else
      playback_.play(glfwGetTime(), range_, frame);
  }
  ImGui::SameLine();
  if (ImGui::Button(">")) frame = playback_.step(frame, 1, range_);
  ImGui::SameLine();
  if (ImGui::Button(">|")) frame = playback_.step(range_.end, 0, range_);
  ImGui::SameLine();
  bool loop = playback_.loop();
  if (ImGui::Checkbox("loop", &loop)) playback_.set_loop(loop);
  ImGui::SameLine(0, 20);
  const std::vector<int> kept = marks(state);
  ImGui::Text("frame %d", frame);
  ImGui::SameLine(0, 20);
  ImGui::TextDisabled("of %d-%d at %g fps, %zu cached for %s%s", range_.start, range_.end, range_.fps, kept.size(),
                      state.viewed.empty() ? "(no node viewed)" : state.viewed.c_str(),
                      shown ? "" : ", evaluating...");

  // The bar: cached frames marked, the current frame as a handle; drag to scrub.
  const ImVec2 at = ImGui::GetCursorScreenPos();
  const float width = std::max(ImGui::GetContentRegionAvail().x, 50.0f), height = 16;
  ImGui::InvisibleButton("##frames", ImVec2(width, height));
  bar_min_ = ImVec2(at.x + 6, at.y);
  bar_max_ = ImVec2(at.x + width - 6, at.y + height);
  if (ImGui::IsItemActive()) {
    playback_.pause();
    frame = frame_at(ImGui::GetIO().MousePos.x);
  }
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("frame %d", frame_at(ImGui::GetIO().MousePos.x));
  ImDrawList* draw = ImGui::GetWindowDrawList();
  draw->AddRectFilled(ImVec2(at.x, at.y), ImVec2(at.x + width, at.y + height), IM_COL32(45, 45, 52, 255), 3);
  // Runs of consecutive cached frames, each one rectangle along the bar's foot.
  const float half = 0.5f * (bar_max_.x - bar_min_.x) / float(std::max(range_.end - range_.start, 1));
  for (std::size_t i = 0; i < kept.size();) {
    std::size_t j = i;
    while (j + 1 < kept.size() && kept[j + 1] == kept[j] + 1) ++j;
    const float x0 = std::max(frame_position(kept[i]).x - half, at.x);
    const float x1 = std::min(frame_position(kept[j]).x + half, at.x + width);
    draw->AddRectFilled(ImVec2(x0, at.y + height - 5), ImVec2(x1, at.y + height), IM_COL32(70, 170, 230, 255));
    i = j + 1;
  }
  const float x = frame_position(frame).x;
  draw->AddRectFilled(ImVec2(x - 2, at.y), ImVec2(x + 2, at.y + height), IM_COL32(240, 190, 60, 255));

  if (frame != doc.frame()) doc.set_frame(frame);
}

}  // namespace loom::editor
