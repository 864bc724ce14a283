#include "value_views.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <imgui.h>

namespace loom::editor {

void draw_plot(const std::vector<double>& values) {
  if (values.empty()) {
    ImGui::TextDisabled("empty list");
    return;
  }
  double lo = 1e300, hi = -1e300;
  for (double v : values)
    if (std::isfinite(v)) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  if (lo > hi) lo = hi = 0;
  if (hi - lo < 1e-300) hi = lo + 1;
  ImGui::Text("%zu values, min %.6g, max %.6g, last %.6g", values.size(), lo, hi, values.back());
  const ImVec2 a = ImGui::GetCursorScreenPos();
  ImVec2 size = ImGui::GetContentRegionAvail();
  size.y = std::max(size.y - 4, 60.0f);
  ImGui::InvisibleButton("plot", size);
  ImDrawList* draw = ImGui::GetWindowDrawList();
  draw->AddRectFilled(a, ImVec2(a.x + size.x, a.y + size.y), IM_COL32(25, 25, 28, 255));
  const float margin = 8;
  auto at = [&](std::size_t i) {
    const float x = values.size() == 1 ? 0.5f : float(i) / float(values.size() - 1);
    const double v = std::isfinite(values[i]) ? values[i] : lo;
    const float y = float((v - lo) / (hi - lo));
    return ImVec2(a.x + margin + x * (size.x - 2 * margin), a.y + size.y - margin - y * (size.y - 2 * margin));
  };
  std::vector<ImVec2> points;
  for (std::size_t i = 0; i < values.size(); ++i) points.push_back(at(i));
  draw->AddPolyline(points.data(), int(points.size()), IM_COL32(120, 200, 255, 255), 0, 2);
  if (ImGui::IsItemHovered()) {
    const float t = (ImGui::GetIO().MousePos.x - a.x - margin) / std::max(1.0f, size.x - 2 * margin);
    const std::size_t i = std::size_t(std::clamp(std::lround(t * float(values.size() - 1)), 0l, long(values.size() - 1)));
    draw->AddCircleFilled(at(i), 4, IM_COL32_WHITE);
    ImGui::SetTooltip("[%zu] = %.8g", i, values[i]);
  }
}

namespace {
void tree(const std::string& key, const json& v) {
  if (v.is_object() || v.is_array()) {
    const std::string label = key + (v.is_object() ? " {" : " [") + std::to_string(v.size()) + (v.is_object() ? "}" : "]");
    if (ImGui::TreeNode(key.c_str(), "%s", label.c_str())) {
      if (v.is_object())
        for (const auto& [k, child] : v.items()) tree(k, child);
      else
        for (std::size_t i = 0; i < v.size(); ++i) tree(std::to_string(i), v[i]);
      ImGui::TreePop();
    }
  } else {
    ImGui::BulletText("%s: %s", key.c_str(), v.dump().c_str());
  }
}
}  // namespace

void draw_json_tree(const json& value) {
  ImGui::BeginChild("json");
  tree("value", value);
  ImGui::EndChild();
}

void draw_value(const Value& value) {
  if (value.is<std::vector<double>>()) return draw_plot(value.as<std::vector<double>>());
  if (value.is<std::vector<int>>()) {
    const auto& ints = value.as<std::vector<int>>();
    return draw_plot(std::vector<double>(ints.begin(), ints.end()));
  }
  const json j = value.to_json();
  if (j.is_object() || (j.is_array() && j.size() > 8)) return draw_json_tree(j);
  if (!j.is_null()) {
    ImGui::TextWrapped("%s", j.dump(1).c_str());
    return;
  }
  ImGui::TextWrapped("%s", value.summary().c_str());
  ImGui::TextDisabled("(no viewer for %s yet)", value.type() ? value.type()->name.c_str() : "?");
}

}  // namespace loom::editor
