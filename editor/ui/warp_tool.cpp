#include "warp_tool.hpp"

#include <cmath>

#include "loom/point_pairs.hpp"

namespace loom::editor {

namespace {

constexpr float kReach = 8;  // screen pixels

double tenth(double v) { return std::round(v * 10) / 10; }
// Whole pixels are written as integers, so graph files stay as people write them.
json number(double v) { return v == std::floor(v) ? json(static_cast<long long>(v)) : json(v); }

json to_literal(const PointPairs& pairs) {
  json out = json::array();
  for (std::size_t i = 0; i < pairs.size(); ++i)
    out.push_back({number(tenth(pairs.p[i].x())), number(tenth(pairs.p[i].y())), number(tenth(pairs.q[i].x())),
                   number(tenth(pairs.q[i].y()))});
  return out;
}

}  // namespace

bool WarpTool::applies(const EditorState& state, const std::string& id) {
  const NodeType* t = state.doc.has_node(id) ? state.doc.node_type(id) : nullptr;
  if (!t) return false;
  const InputSpec* pairs = t->spec.find_input("pairs");
  return pairs && pairs->type == &type_of<PointPairs>() && !state.doc.link(id, "pairs");
}

void WarpTool::draw(EditorState& state, const std::string& id, const ImageView& view) {
  GraphDocument& doc = state.doc;
  PointPairs pairs;
  try {
    const json literal = doc.literal(id, "pairs");
    if (!literal.is_null()) pairs = TypeTraits<PointPairs>::from_json(literal);
  } catch (const std::exception&) {
    return;  // the property panel and the canvas show why the literal is bad
  }
  ImDrawList* draw = ImGui::GetWindowDrawList();
  ImGuiIO& io = ImGui::GetIO();
  const ImVec2 mouse = io.MousePos;
  const ImVec2 at = view.to_image(mouse);

  // The nearest end within reach, q before p (q is what one usually drags).
  int hit = -1;
  bool hit_q = true;
  float best = kReach;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    for (int end = 0; end < 2; ++end) {
      const Vec2& v = end ? pairs.p[i] : pairs.q[i];
      const ImVec2 s = view.to_screen(v.x(), v.y());
      const float d = std::hypot(s.x - mouse.x, s.y - mouse.y);
      if (d < best) {
        best = d;
        hit = int(i);
        hit_q = end == 0;
      }
    }
  }

  bool changed = false;
  if (view.hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
    if (hit >= 0) {
      dragging_ = hit;
      dragging_q_ = hit_q;
    } else {
      pairs.p.push_back(Vec2(at.x, at.y));
      pairs.q.push_back(Vec2(at.x, at.y));
      dragging_ = int(pairs.size()) - 1;
      dragging_q_ = true;
      changed = true;
    }
  } else if (view.hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Right) && hit >= 0) {
    pairs.p.erase(pairs.p.begin() + hit);
    pairs.q.erase(pairs.q.begin() + hit);
    doc.set_input(id, "pairs", to_literal(pairs));
    return;
  }
  if (dragging_ >= 0 && dragging_ < int(pairs.size())) {
    if (ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
      Vec2& v = dragging_q_ ? pairs.q[std::size_t(dragging_)] : pairs.p[std::size_t(dragging_)];
      const Vec2 next(tenth(at.x), tenth(at.y));
      if (next != v) {
        v = next;
        changed = true;
      }
    } else {
      dragging_ = -1;
      doc.end_merge();
    }
  }
  if (changed) doc.set_input(id, "pairs", to_literal(pairs), "warp-drag");

  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const ImVec2 p = view.to_screen(pairs.p[i].x(), pairs.p[i].y());
    const ImVec2 q = view.to_screen(pairs.q[i].x(), pairs.q[i].y());
    draw->AddLine(p, q, IM_COL32(255, 255, 255, 200), 1.5f);
    draw->AddCircleFilled(p, 4, IM_COL32(80, 140, 255, 255));
    draw->AddCircleFilled(q, 4, IM_COL32(255, 80, 80, 255));
  }
  if (hit >= 0 && dragging_ < 0)
    ImGui::SetTooltip("pair %d: drag to move %s, right-click to delete", hit, hit_q ? "q" : "p");
}

}  // namespace loom::editor
