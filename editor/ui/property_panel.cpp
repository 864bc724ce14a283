#include "property_panel.hpp"

#include <imgui.h>
#include <imgui_stdlib.h>

#include "loom/image.hpp"
#include "loom/mesh.hpp"

namespace loom::editor {

namespace {

// Reads up to n numbers from a JSON array (missing ones stay as they are).
template <class T>
void numbers(const json& v, T* out, int n) {
  if (!v.is_array()) return;
  for (int i = 0; i < n && i < int(v.size()); ++i)
    if (v[std::size_t(i)].is_number()) out[i] = v[std::size_t(i)].get<T>();
}

}  // namespace

void PropertyPanel::draw(EditorState& state, FileDialog& files) {
  GraphDocument& doc = state.doc;
  if (state.selection.size() != 1 || !doc.has_node(*state.selection.begin())) {
    ImGui::TextDisabled(state.selection.empty() ? "Select a node to edit its inputs."
                                                : "Several nodes selected.");
    return;
  }
  const std::string id = *state.selection.begin();
  if (id != rects_node_) rects_.clear();
  rects_node_ = id;
  const NodeType* t = doc.node_type(id);
  ImGui::Text("%s", id.c_str());
  ImGui::SameLine();
  ImGui::TextDisabled("%s", doc.type_name(id).c_str());
  if (!t) {
    ImGui::TextColored(ImVec4(1, 0.5f, 0.5f, 1), "unknown node type: its plugin is not loaded");
    return;
  }
  ImGui::TextWrapped("%s", t->spec.description.c_str());
  if (const NodeReport* r = state.report(id)) {
    if (!r->error.empty()) ImGui::TextColored(ImVec4(1, 0.5f, 0.5f, 1), "%s", r->error.c_str());
    for (const auto& w : r->warnings) ImGui::TextColored(ImVec4(1, 0.8f, 0.4f, 1), "warning: %s", w.c_str());
  }
  auto node_issues = state.issues.find(id);
  if (node_issues != state.issues.end() && node_issues->second.count(""))
    ImGui::TextColored(ImVec4(1, 0.5f, 0.5f, 1), "%s", node_issues->second.at("").c_str());
  ImGui::Separator();
  ImGui::PushItemWidth(-110);
  for (const InputSpec& spec : t->spec.inputs) {
    ImGui::PushID(spec.name.c_str());
    draw_input(state, files, id, spec);
    if (node_issues != state.issues.end() && node_issues->second.count(spec.name))
      ImGui::TextColored(ImVec4(1, 0.5f, 0.5f, 1), "%s", node_issues->second.at(spec.name).c_str());
    ImGui::PopID();
  }
  ImGui::PopItemWidth();
}

void PropertyPanel::draw_input(EditorState& state, FileDialog& files, const std::string& id,
                               const InputSpec& spec) {
  GraphDocument& doc = state.doc;
  const std::string key = id + "." + spec.name;
  const std::string label = spec.name;
  auto tooltip = [&] {
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("%s (%s%s)\n%s", spec.name.c_str(), spec.type->name.c_str(),
                        spec.optional ? ", optional" : "", spec.description.c_str());
  };
  if (auto l = doc.link(id, spec.name)) {
    ImGui::TextColored(ImVec4(0.6f, 0.8f, 1, 1), "%s  <- %s.%s (linked)", label.c_str(), l->node.c_str(),
                       l->output.c_str());
    tooltip();
    ImGui::SameLine();
    if (ImGui::SmallButton("unlink")) doc.disconnect(id, spec.name);
    return;
  }
  const json literal = doc.literal(id, spec.name);
  const json value = literal.is_null() ? spec.default_value : literal;
  const TypeInfo* type = spec.type;
  const std::string merge = "input:" + key;
  bool changed = false;
  json next;

  if (value.is_null() && (type == &type_of<Image>() || type == &type_of<Mesh>() || !type->literal())) {
    ImGui::TextDisabled("%s: link an input (%s)%s", label.c_str(), type->name.c_str(),
                        spec.required() ? ", required" : ", optional");
    tooltip();
    return;
  }
  if (type == &type_of<bool>()) {
    bool b = value.is_boolean() && value.get<bool>();
    if ((changed = ImGui::Checkbox(label.c_str(), &b))) next = b;
  } else if (type == &type_of<int>()) {
    int v = value.is_number() ? value.get<int>() : 0;
    if (spec.min && spec.max && *spec.max - *spec.min <= 10000)
      changed = ImGui::SliderInt(label.c_str(), &v, int(*spec.min), int(*spec.max));
    else
      changed = ImGui::DragInt(label.c_str(), &v, 0.25f, spec.min ? int(*spec.min) : 0, spec.max ? int(*spec.max) : 0);
    if (changed) next = v;
  } else if (type == &type_of<double>()) {
    float v = value.is_number() ? value.get<float>() : 0.0f;
    if (spec.min && spec.max && *spec.max - *spec.min <= 10000)
      changed = ImGui::SliderFloat(label.c_str(), &v, float(*spec.min), float(*spec.max), "%.4g");
    else
      changed = ImGui::DragFloat(label.c_str(), &v, 0.01f, spec.min ? float(*spec.min) : 0.0f,
                                 spec.max ? float(*spec.max) : 0.0f, "%.4g");
    if (changed) next = double(v);
  } else if (type == &enum_type()) {
    const std::string current = value.is_string() ? value.get<std::string>() : "";
    if (ImGui::BeginCombo(label.c_str(), current.c_str())) {
      for (const auto& choice : spec.choices)
        if (ImGui::Selectable(choice.c_str(), choice == current)) {
          next = choice;
          changed = true;
        }
      ImGui::EndCombo();
    }
  } else if (type == &type_of<std::string>()) {
    std::string s = value.is_string() ? value.get<std::string>() : "";
    if (spec.role != InputRole::value) {
      ImGui::SetNextItemWidth(-150);
      changed = ImGui::InputText(label.c_str(), &s);
      ImGui::SameLine();
      if (ImGui::SmallButton("...")) {
        const auto base = doc.file().empty() ? std::filesystem::current_path() : doc.file().parent_path();
        files.open("input:" + key, "Choose " + key, s.empty() ? base : base / s, spec.role == InputRole::output_file);
      }
    } else {
      changed = ImGui::InputText(label.c_str(), &s);
    }
    if (changed) next = s;
  } else if (type == &type_of<Color>()) {
    float c[4] = {0, 0, 0, 1};
    numbers(value, c, 4);
    const bool alpha = value.is_array() && value.size() == 4;
    changed = alpha ? ImGui::ColorEdit4(label.c_str(), c, ImGuiColorEditFlags_Float)
                    : ImGui::ColorEdit3(label.c_str(), c, ImGuiColorEditFlags_Float);
    if (changed) next = alpha ? json{c[0], c[1], c[2], c[3]} : json{c[0], c[1], c[2]};
  } else if (type == &type_of<Vec2i>() || type == &type_of<Vec3i>()) {
    int v[3] = {0, 0, 0};
    const int n = type == &type_of<Vec2i>() ? 2 : 3;
    numbers(value, v, n);
    changed = n == 2 ? ImGui::DragInt2(label.c_str(), v, 0.5f) : ImGui::DragInt3(label.c_str(), v, 0.5f);
    if (changed) next = n == 2 ? json{v[0], v[1]} : json{v[0], v[1], v[2]};
  } else if (type == &type_of<Vec2>() || type == &type_of<Vec3>()) {
    float v[3] = {0, 0, 0};
    const int n = type == &type_of<Vec2>() ? 2 : 3;
    numbers(value, v, n);
    changed = n == 2 ? ImGui::DragFloat2(label.c_str(), v, 0.01f) : ImGui::DragFloat3(label.c_str(), v, 0.01f);
    if (changed) next = n == 2 ? json{v[0], v[1]} : json{v[0], v[1], v[2]};
  } else {
    // Lists, point pairs, JSON: edited as text, applied when valid.
    auto it = text_.find(key);
    if (it == text_.end() || !ImGui::IsWindowFocused(ImGuiFocusedFlags_ChildWindows))
      it = text_.insert_or_assign(key, value.is_null() ? std::string() : value.dump()).first;
    ImGui::TextUnformatted(label.c_str());
    tooltip();
    ImGui::InputTextMultiline("##json", &it->second, ImVec2(-1, ImGui::GetTextLineHeight() * 4));
    if (ImGui::IsItemDeactivatedAfterEdit()) {
      try {
        next = json::parse(it->second);
        changed = true;
        error_.erase(key);
      } catch (const std::exception& e) {
        error_[key] = e.what();
      }
    }
    if (error_.count(key)) ImGui::TextColored(ImVec4(1, 0.5f, 0.5f, 1), "not JSON: %s", error_[key].c_str());
  }
  rects_[spec.name] = {ImGui::GetItemRectMin(), ImGui::GetItemRectMax()};
  tooltip();
  if (ImGui::IsItemDeactivated()) doc.end_merge();
  if (changed) doc.set_input(id, spec.name, next, merge);
  if (auto chosen = files.take("input:" + key)) {
    std::error_code ec;
    const auto base = doc.file().empty() ? std::filesystem::current_path() : doc.file().parent_path();
    const auto relative = std::filesystem::relative(*chosen, base, ec);
    doc.set_input(id, spec.name, (ec || relative.empty() ? *chosen : relative).string());
  }
  if (!literal.is_null()) {
    ImGui::SameLine();
    if (ImGui::SmallButton("reset")) doc.reset_input(id, spec.name);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("back to the default: %s", spec.default_value.dump().c_str());
  }
}

}  // namespace loom::editor
