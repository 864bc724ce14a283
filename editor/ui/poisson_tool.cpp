#include "poisson_tool.hpp"

#include <cmath>

namespace loom::editor {

namespace {

// The region as an outline in source pixels, from the node's literals.
std::vector<ImVec2> region_outline(const GraphDocument& doc, const std::string& id) {
  std::vector<ImVec2> outline;
  const json polygon = doc.literal(id, "polygon");
  const json rectangle = doc.literal(id, "rectangle");
  if (polygon.is_array()) {
    for (const auto& p : polygon)
      if (p.is_array() && p.size() == 2 && p[0].is_number() && p[1].is_number())
        outline.emplace_back(p[0].get<float>(), p[1].get<float>());
  } else if (rectangle.is_array() && rectangle.size() == 4) {
    const float x = rectangle[0].get<float>(), y = rectangle[1].get<float>();
    const float w = rectangle[2].get<float>(), h = rectangle[3].get<float>();
    outline = {{x, y}, {x + w, y}, {x + w, y + h}, {x, y + h}};
  }
  return outline;
}

void polyline(ImDrawList* draw, const std::vector<ImVec2>& points, const ImageView& view, ImVec2 shift,
              bool closed, ImU32 color) {
  std::vector<ImVec2> screen;
  for (const ImVec2& p : points) screen.push_back(view.to_screen(p.x + shift.x, p.y + shift.y));
  draw->AddPolyline(screen.data(), int(screen.size()), IM_COL32(0, 0, 0, 160), closed ? ImDrawFlags_Closed : 0, 4);
  draw->AddPolyline(screen.data(), int(screen.size()), color, closed ? ImDrawFlags_Closed : 0, 2);
}

}  // namespace

bool PoissonTool::applies(const EditorState& state, const std::string& id) {
  const NodeType* t = state.doc.has_node(id) ? state.doc.node_type(id) : nullptr;
  if (!t) return false;
  const InputSpec* offset = t->spec.find_input("offset");
  return offset && offset->type == &type_of<Vec2i>() && t->spec.find_input("source") && t->spec.find_input("target") &&
         t->spec.find_input("polygon") && t->spec.find_input("rectangle");
}

bool PoissonTool::toolbar() {
  int mode = int(mode_);
  ImGui::TextDisabled("region:");
  ImGui::SameLine();
  bool changed = ImGui::RadioButton("move on target", &mode, int(Mode::move));
  ImGui::SameLine();
  changed |= ImGui::RadioButton("draw rectangle", &mode, int(Mode::rectangle));
  ImGui::SameLine();
  changed |= ImGui::RadioButton("draw polygon", &mode, int(Mode::polygon));
  if (changed) set_mode(Mode(mode));
  return mode_ != Mode::move;
}

void PoissonTool::draw(EditorState& state, const std::string& id, const ImageView& view) {
  if (mode_ == Mode::move)
    move_region(state, id, view);
  else
    draw_region(state, id, view);
}

void PoissonTool::move_region(EditorState& state, const std::string& id, const ImageView& view) {
  GraphDocument& doc = state.doc;
  const json offset_literal = doc.literal(id, "offset");
  const json offset = offset_literal.is_null() ? doc.node_type(id)->spec.find_input("offset")->default_value
                                               : offset_literal;
  int current[2] = {0, 0};
  if (offset.is_array() && offset.size() == 2) current[0] = offset[0].get<int>(), current[1] = offset[1].get<int>();
  const ImVec2 at = view.to_image(ImGui::GetIO().MousePos);
  if (view.hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
    dragging_ = true;
    press_ = at;
    offset_at_press_[0] = current[0];
    offset_at_press_[1] = current[1];
  }
  if (dragging_) {
    if (ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
      const int next[2] = {offset_at_press_[0] + int(std::lround(at.x - press_.x)),
                           offset_at_press_[1] + int(std::lround(at.y - press_.y))};
      if (next[0] != current[0] || next[1] != current[1]) {
        doc.set_input(id, "offset", {next[0], next[1]}, "poisson-drag");
        current[0] = next[0];
        current[1] = next[1];
      }
    } else {
      dragging_ = false;
      doc.end_merge();
    }
  }
  const auto outline = region_outline(doc, id);
  if (!outline.empty())
    polyline(ImGui::GetWindowDrawList(), outline, view, ImVec2(float(current[0]), float(current[1])), true,
             IM_COL32(255, 220, 80, 255));
  if (view.hovered && !dragging_) ImGui::SetTooltip("drag to move the region over the target");
}

void PoissonTool::draw_region(EditorState& state, const std::string& id, const ImageView& view) {
  GraphDocument& doc = state.doc;
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const ImVec2 raw = view.to_image(ImGui::GetIO().MousePos);
  const ImVec2 at(std::round(raw.x), std::round(raw.y));
  // The region the node has now, dimmed, for reference.
  const auto outline = region_outline(doc, id);
  if (!outline.empty()) polyline(draw, outline, view, ImVec2(0, 0), true, IM_COL32(255, 255, 255, 110));

  if (mode_ == Mode::rectangle) {
    if (view.hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) draft_ = {at, at};
    if (draft_.size() == 2) {
      if (ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
        draft_[1] = at;
      } else {
        const float x0 = std::min(draft_[0].x, draft_[1].x), y0 = std::min(draft_[0].y, draft_[1].y);
        const float w = std::abs(draft_[1].x - draft_[0].x), h = std::abs(draft_[1].y - draft_[0].y);
        if (w >= 2 && h >= 2)
          doc.set_inputs(id, {{"rectangle", {int(x0), int(y0), int(w), int(h)}}, {"polygon", nullptr}, {"mask", nullptr}});
        set_mode(Mode::move);
        return;
      }
      const ImVec2 a = draft_[0], b = draft_[1];
      polyline(draw, {a, {b.x, a.y}, b, {a.x, b.y}}, view, ImVec2(0, 0), true, IM_COL32(255, 220, 80, 255));
    }
    if (view.hovered) ImGui::SetTooltip("drag a rectangle on the source");
    return;
  }
  // Polygon: click vertices; click the first vertex (or double-click) to close.
  if (view.hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Right)) draft_.clear();
  if (view.hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
    const ImVec2 first = draft_.empty() ? ImVec2() : view.to_screen(draft_[0].x, draft_[0].y);
    const ImVec2 mouse = ImGui::GetIO().MousePos;
    const bool closes = draft_.size() >= 3 && (std::hypot(first.x - mouse.x, first.y - mouse.y) < 8 ||
                                               ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left));
    if (closes) {
      json points = json::array();
      for (const ImVec2& p : draft_) points.push_back({p.x, p.y});
      doc.set_inputs(id, {{"polygon", points}, {"rectangle", nullptr}, {"mask", nullptr}});
      set_mode(Mode::move);
      return;
    }
    draft_.push_back(at);
  }
  if (!draft_.empty()) {
    auto with_mouse = draft_;
    with_mouse.push_back(at);
    polyline(draw, with_mouse, view, ImVec2(0, 0), false, IM_COL32(255, 220, 80, 255));
  }
  if (view.hovered)
    ImGui::SetTooltip(draft_.size() >= 3 ? "click the first vertex to close; right-click to start over"
                                         : "click the polygon's vertices on the source");
}

}  // namespace loom::editor
