#include "draw_tool.hpp"

#include <algorithm>
#include <cmath>

namespace loom::editor {

namespace {

double rounded(double v) { return std::round(v * 1000) / 1000; }
json color(const float* c) { return {rounded(c[0]), rounded(c[1]), rounded(c[2]), rounded(c[3])}; }
json point(ImVec2 p) { return {std::round(double(p.x) * 10) / 10, std::round(double(p.y) * 10) / 10}; }

const char* kShapes[] = {"line", "rectangle", "ellipse", "polygon", "freehand"};

}  // namespace

bool DrawTool::applies(const EditorState& state, const std::string& id) {
  const NodeType* t = state.doc.has_node(id) ? state.doc.node_type(id) : nullptr;
  if (!t) return false;
  const InputSpec* figures = t->spec.find_input("figures");
  return figures && figures->type == &type_of<json>() && !state.doc.link(id, "figures");
}

void DrawTool::toolbar() {
  int s = int(shape);
  for (int i = 0; i < 5; ++i) {
    if (i) ImGui::SameLine();
    if (ImGui::RadioButton(kShapes[i], &s, i)) {
      shape = Shape(i);
      draft_.clear();
    }
  }
  ImGui::SameLine();
  ImGui::ColorEdit4("stroke", stroke, ImGuiColorEditFlags_NoInputs);
  ImGui::SameLine();
  ImGui::Checkbox("fill", &fill);
  ImGui::SameLine();
  ImGui::ColorEdit4("##fill", fill_color, ImGuiColorEditFlags_NoInputs);
  ImGui::SameLine();
  ImGui::SetNextItemWidth(80);
  ImGui::SliderFloat("width", &width, 0, 20, "%.0f");
}

json DrawTool::figure(const std::vector<ImVec2>& p) const {
  json f = {{"stroke", color(stroke)}, {"width", rounded(width)}};
  const bool closed = shape == Shape::rectangle || shape == Shape::ellipse || shape == Shape::polygon;
  if (closed && fill) f["fill"] = color(fill_color);
  switch (shape) {
    case Shape::line:
      f["type"] = "line";
      f["from"] = point(p.front());
      f["to"] = point(p.back());
      break;
    case Shape::rectangle:
      f["type"] = "rectangle";
      f["min"] = point(ImVec2(std::min(p.front().x, p.back().x), std::min(p.front().y, p.back().y)));
      f["max"] = point(ImVec2(std::max(p.front().x, p.back().x), std::max(p.front().y, p.back().y)));
      break;
    case Shape::ellipse:  // dragged as its bounding box
      f["type"] = "ellipse";
      f["center"] = point(ImVec2((p.front().x + p.back().x) / 2, (p.front().y + p.back().y) / 2));
      f["axes"] = point(ImVec2(std::abs(p.back().x - p.front().x) / 2, std::abs(p.back().y - p.front().y) / 2));
      f["angle"] = 0;
      break;
    case Shape::polygon:
    case Shape::freehand: {
      f["type"] = shape == Shape::polygon ? "polygon" : "freehand";
      json points = json::array();
      for (const ImVec2& q : p) points.push_back(point(q));
      f["points"] = points;
      break;
    }
  }
  return f;
}

void DrawTool::preview(const ImageView& view) const {
  if (draft_.empty()) return;
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const ImU32 line = ImGui::ColorConvertFloat4ToU32(ImVec4(stroke[0], stroke[1], stroke[2], stroke[3]));
  const float w = std::max(1.0f, width * view.scale);
  const ImVec2 a = view.to_screen(draft_.front().x, draft_.front().y);
  const ImVec2 b = view.to_screen(draft_.back().x, draft_.back().y);
  switch (shape) {
    case Shape::line: draw->AddLine(a, b, line, w); break;
    case Shape::rectangle:
      draw->AddRect(ImVec2(std::min(a.x, b.x), std::min(a.y, b.y)), ImVec2(std::max(a.x, b.x), std::max(a.y, b.y)), line, 0, 0, w);
      break;
    case Shape::ellipse: {
      const ImVec2 c((a.x + b.x) / 2, (a.y + b.y) / 2);
      const float rx = std::abs(b.x - a.x) / 2, ry = std::abs(b.y - a.y) / 2;
      std::vector<ImVec2> points;
      for (int i = 0; i < 64; ++i) {
        const float t = 6.2831853f * float(i) / 64;
        points.emplace_back(c.x + rx * std::cos(t), c.y + ry * std::sin(t));
      }
      draw->AddPolyline(points.data(), int(points.size()), line, ImDrawFlags_Closed, w);
      break;
    }
    case Shape::polygon:
    case Shape::freehand: {
      std::vector<ImVec2> points;
      for (const ImVec2& p : draft_) points.push_back(view.to_screen(p.x, p.y));
      if (shape == Shape::polygon) points.push_back(ImGui::GetIO().MousePos);
      draw->AddPolyline(points.data(), int(points.size()), line, 0, w);
      break;
    }
  }
}

void DrawTool::draw(EditorState& state, const std::string& id, const ImageView& view) {
  GraphDocument& doc = state.doc;
  const ImVec2 mouse = ImGui::GetIO().MousePos;
  const ImVec2 at = view.to_image(mouse);
  auto commit = [&] {
    json figures = doc.literal(id, "figures");
    if (!figures.is_array()) figures = json::array();
    figures.push_back(figure(draft_));
    doc.set_input(id, "figures", figures);
    draft_.clear();
  };
  if (shape == Shape::polygon) {
    if (view.hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Right)) draft_.clear();
    if (view.hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
      const ImVec2 first = draft_.empty() ? ImVec2() : view.to_screen(draft_[0].x, draft_[0].y);
      if (draft_.size() >= 3 && (std::hypot(first.x - mouse.x, first.y - mouse.y) < 8 ||
                                 ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left)))
        commit();
      else
        draft_.push_back(at);
    }
  } else {
    if (view.hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
      draft_ = {at, at};
      dragging_ = true;
    }
    if (dragging_) {
      if (ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
        const ImVec2 last = draft_.back();
        if (shape == Shape::freehand) {
          if (std::hypot(at.x - last.x, at.y - last.y) * view.scale >= 3) draft_.push_back(at);
        } else {
          draft_.back() = at;
        }
      } else {
        dragging_ = false;
        const ImVec2 a = draft_.front(), b = draft_.back();
        if (std::hypot(a.x - b.x, a.y - b.y) * view.scale >= 3)
          commit();
        else
          draft_.clear();
      }
    }
  }
  preview(view);
}

}  // namespace loom::editor
