#include "property_panel.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include <imgui.h>
#include <imgui_stdlib.h>

namespace loom::editor {

namespace {

// Reads up to n numbers from a JSON array (missing ones stay as they are).
template <class T>
void numbers(const json& v, T* out, int n) {
  if (!v.is_array()) return;
  for (int i = 0; i < n && i < int(v.size()); ++i)
    if (v[std::size_t(i)].is_number()) out[i] = v[std::size_t(i)].get<T>();
}

const ImVec4 kError(1, 0.5f, 0.5f, 1);
const ImVec4 kGroupText(0.8f, 0.65f, 1, 1);  // what the group's interface gives
constexpr float kMinWidget = 180;  // the narrowest a widget column gets before the pane scrolls

void tooltip(const InputSpec& spec) {
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("%s (%s%s)\n%s", spec.name.c_str(), spec.type->name.c_str(),
                      spec.optional ? ", optional" : "", spec.description.c_str());
}

// A colour picker works in floats: components are written rounded to 1e-6
// so a picked colour reads "0.8", not "0.800000011920929".
double picked(float c) { return std::round(double(c) * 1e6) / 1e6; }

// Ints and doubles (never through a float: a typed value is kept exactly).
bool edit_number(InputWidget widget, const InputSpec& spec, const json& value, json& next) {
  const double lo = spec.min.value_or(0), hi = spec.max.value_or(0);
  switch (widget) {
    case InputWidget::int_slider:
    case InputWidget::int_drag: {
      int v = value.is_number() ? value.get<int>() : 0;
      const int ilo = int(lo), ihi = int(hi);
      const bool edited = widget == InputWidget::int_slider
                              ? ImGui::SliderInt("##v", &v, ilo, ihi)
                              : ImGui::DragScalar("##v", ImGuiDataType_S32, &v, 0.25f, spec.min ? &ilo : nullptr,
                                                  spec.max ? &ihi : nullptr);
      return edited && (next = v, true);
    }
    case InputWidget::number_slider:
    case InputWidget::number_drag: {
      double v = value.is_number() ? value.get<double>() : 0.0;
      const bool edited = widget == InputWidget::number_slider
                              ? ImGui::SliderScalar("##v", ImGuiDataType_Double, &v, &lo, &hi, "%.6g")
                              : ImGui::DragScalar("##v", ImGuiDataType_Double, &v, 0.01f, spec.min ? &lo : nullptr,
                                                  spec.max ? &hi : nullptr, "%.6g");
      return edited && (next = v, true);
    }
    default: return false;
  }
}

bool edit_vector(InputWidget widget, const InputSpec& spec, const json& value, json& next) {
  const double lo = spec.min.value_or(0), hi = spec.max.value_or(0);
  const bool clamped = spec.min && spec.max;
  switch (widget) {
    case InputWidget::color: {
      float c[4] = {0, 0, 0, 1};
      numbers(value, c, 4);
      const bool alpha = value.is_array() && value.size() == 4;
      const bool edited = alpha ? ImGui::ColorEdit4("##v", c, ImGuiColorEditFlags_Float)
                                : ImGui::ColorEdit3("##v", c, ImGuiColorEditFlags_Float);
      if (edited) next = alpha ? json{picked(c[0]), picked(c[1]), picked(c[2]), picked(c[3])}
                               : json{picked(c[0]), picked(c[1]), picked(c[2])};
      return edited;
    }
    case InputWidget::int_vector: {
      int v[3] = {0, 0, 0};
      const int n = vector_size(spec);
      numbers(value, v, n);
      if (!ImGui::DragScalarN("##v", ImGuiDataType_S32, v, n, 0.5f)) return false;
      next = json(std::vector<int>(v, v + n));
      return true;
    }
    case InputWidget::number_vector: {
      double v[3] = {0, 0, 0};
      const int n = vector_size(spec);
      numbers(value, v, n);
      if (!ImGui::DragScalarN("##v", ImGuiDataType_Double, v, n, 0.01f, clamped ? &lo : nullptr,
                              clamped ? &hi : nullptr, "%.6g"))
        return false;
      next = json(std::vector<double>(v, v + n));
      return true;
    }
    default: return false;
  }
}

}  // namespace

void PropertyPanel::draw(EditorState& state, FileDialog& files) {
  GraphDocument& doc = state.doc;
  const ImVec2 at = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
  visible_ = {at, ImVec2(at.x + size.x, at.y + size.y)};
  if (state.selection.size() != 1 || !doc.has_node(*state.selection.begin())) {
    ImGui::TextDisabled(state.selection.empty() ? "Select a node to edit its inputs."
                                                : "Several nodes selected.");
    return;
  }
  const std::string id = *state.selection.begin();
  if (id != rects_node_) {
    widgets_.clear();
    labels_.clear();
    buttons_.clear();
  }
  rects_node_ = id;
  enter_button_.reset();
  const NodeType* t = doc.node_type(id);
  ImGui::Text("%s", id.c_str());
  ImGui::SameLine();
  ImGui::TextDisabled("%s", doc.type_name(id).c_str());
  if (!t) {
    ImGui::TextColored(kError, "unknown node type: its plugin is not loaded");
    return;
  }
  ImGui::TextWrapped("%s", t->spec.description.c_str());
  // Entering or ungrouping leaves this level: the node is not here any more.
  if (group_actions(state, id)) return;
  if (const NodeReport* r = state.report(id)) {
    if (!r->error.empty()) ImGui::TextColored(kError, "%s", r->error.c_str());
    for (const auto& w : r->warnings) ImGui::TextColored(ImVec4(1, 0.8f, 0.4f, 1), "warning: %s", w.c_str());
  }
  auto node_issues = state.issues.find(id);
  if (node_issues != state.issues.end() && node_issues->second.count(""))
    ImGui::TextColored(kError, "%s", node_issues->second.at("").c_str());
  ImGui::Separator();

  float names = 0;
  for (const InputSpec& spec : t->spec.inputs) names = std::max(names, ImGui::CalcTextSize(spec.name.c_str()).x);
  const ImGuiStyle& style = ImGui::GetStyle();
  const float buttons = ImGui::CalcTextSize("unlink").x + style.FramePadding.x * 2;
  const float needed = names + kMinWidget + buttons + style.CellPadding.x * 6;
  const float width = std::max(ImGui::GetContentRegionAvail().x, needed);
  if (!ImGui::BeginTable("inputs", 3, ImGuiTableFlags_None, ImVec2(width, 0))) return;
  ImGui::TableSetupColumn("name", ImGuiTableColumnFlags_WidthFixed, names);
  ImGui::TableSetupColumn("widget", ImGuiTableColumnFlags_WidthStretch);
  ImGui::TableSetupColumn("reset", ImGuiTableColumnFlags_WidthFixed, buttons);
  for (const InputSpec& spec : t->spec.inputs) {
    ImGui::PushID(spec.name.c_str());
    ImGui::TableNextRow();
    ImGui::TableSetColumnIndex(0);
    ImGui::AlignTextToFramePadding();
    const bool set = doc.link(id, spec.name) || !doc.literal(id, spec.name).is_null();
    if (set)
      ImGui::TextUnformatted(spec.name.c_str());
    else
      ImGui::TextDisabled("%s", spec.name.c_str());
    labels_[spec.name] = {ImGui::GetItemRectMin(), ImGui::GetItemRectMax()};
    tooltip(spec);
    promote_menu(state, id, spec);
    draw_input(state, files, id, spec);
    if (node_issues != state.issues.end() && node_issues->second.count(spec.name)) {
      ImGui::TableSetColumnIndex(1);
      ImGui::TextColored(kError, "%s", node_issues->second.at(spec.name).c_str());
    }
    ImGui::PopID();
  }
  ImGui::EndTable();
}

// For a group node: enter it and ungroup it. Inside a group: how to promote
// an input. True when the node left the level shown (entered, ungrouped).
bool PropertyPanel::group_actions(EditorState& state, const std::string& id) {
  GraphDocument& doc = state.doc;
  if (doc.is_group_node(id)) {
    const bool repeat = doc.is_repeat(id);
    const bool clicked = ImGui::SmallButton(repeat ? "enter body" : "enter group");
    enter_button_ = Rect{ImGui::GetItemRectMin(), ImGui::GetItemRectMax()};
    if (clicked) {
      state.enter(id);
      return true;
    }
    if (repeat) return false;
    ImGui::SameLine();
    if (ImGui::SmallButton("ungroup")) {
      const auto added = doc.ungroup(id);
      state.selection = {added.begin(), added.end()};
      return true;
    }
  } else if (doc.has_interface()) {
    ImGui::TextDisabled("right-click an input's name to make it an input of the group");
  }
  return false;
}

// Right-click on an input's name inside a group: "promote to group input",
// or set it for the instance entered only (promoted, the instance given the
// value it has now: nothing evaluated changes until it is edited).
void PropertyPanel::promote_menu(EditorState& state, const std::string& id, const InputSpec& spec) {
  GraphDocument& doc = state.doc;
  if (!doc.has_interface() || doc.link(id, spec.name) || !doc.promoted_as(id, spec.name).empty()) return;
  if (ImGui::BeginPopupContextItem("promote")) {
    if (ImGui::MenuItem("Promote to group input")) doc.promote(id, spec.name);
    const std::string instance = doc.instance_id();
    if (!instance.empty() && ImGui::MenuItem(("Set for this instance only (" + instance + ")").c_str())) {
      const json literal = doc.literal(id, spec.name);
      doc.set_for_instance(id, spec.name, literal.is_null() ? spec.default_value : literal);
    }
    ImGui::EndPopup();
  }
}

// An inner input fed by the interface, inside the instance entered: the
// value that instance gives (editable here; other instances keep theirs).
void PropertyPanel::draw_instance_input(EditorState& state, FileDialog& files, const InputSpec& spec,
                                        const std::string& name) {
  GraphDocument& doc = state.doc;
  const std::string instance = doc.instance_id();
  ImGui::AlignTextToFramePadding();
  if (auto l = doc.instance_link(name)) {
    ImGui::TextColored(kGroupText, "<- %s.%s <- %s.%s", instance.c_str(), name.c_str(), l->node.c_str(),
                       l->output.c_str());
    widgets_[spec.name] = {ImGui::GetItemRectMin(), ImGui::GetItemRectMax()};
    return;
  }
  ImGui::TextColored(kGroupText, "%s:", instance.c_str());
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("the value instance %s gives the group's input %s; other instances keep theirs", instance.c_str(),
                      name.c_str());
  ImGui::SameLine();
  const json literal = doc.instance_literal(name);
  const json declared = doc.interface_inputs().value(name, json::object());
  const json value = !literal.is_null() ? literal : declared.value("default", spec.default_value);
  json next;
  const bool changed = edit_literal(state, files, instance + "." + name, spec, value, next);
  widgets_[spec.name] = {ImGui::GetItemRectMin(), ImGui::GetItemRectMax()};
  if (ImGui::IsItemDeactivated()) doc.end_merge();
  if (changed) doc.set_instance_input(name, next, "instance:" + instance + "." + name);
  if (!literal.is_null()) {
    ImGui::TableSetColumnIndex(2);
    if (ImGui::SmallButton("reset")) doc.reset_instance_input(name);
    buttons_[spec.name] = {ImGui::GetItemRectMin(), ImGui::GetItemRectMax()};
  }
}

void PropertyPanel::draw_input(EditorState& state, FileDialog& files, const std::string& id,
                               const InputSpec& spec) {
  GraphDocument& doc = state.doc;
  ImGui::TableSetColumnIndex(1);
  buttons_.erase(spec.name);
  if (const std::string promoted = doc.promoted_as(id, spec.name); !promoted.empty()) {
    if (!doc.instance_id().empty()) return draw_instance_input(state, files, spec, promoted);
    ImGui::AlignTextToFramePadding();
    ImGui::TextColored(kGroupText, "<- group input %s", promoted.c_str());
    widgets_[spec.name] = {ImGui::GetItemRectMin(), ImGui::GetItemRectMax()};
    return;
  }
  if (auto l = doc.link(id, spec.name)) {
    ImGui::AlignTextToFramePadding();
    ImGui::TextColored(ImVec4(0.6f, 0.8f, 1, 1), "<- %s.%s", l->node.c_str(), l->output.c_str());
    widgets_[spec.name] = {ImGui::GetItemRectMin(), ImGui::GetItemRectMax()};
    tooltip(spec);
    ImGui::TableSetColumnIndex(2);
    if (ImGui::SmallButton("unlink")) doc.disconnect(id, spec.name);
    buttons_[spec.name] = {ImGui::GetItemRectMin(), ImGui::GetItemRectMax()};
    return;
  }
  const json literal = doc.literal(id, spec.name);
  const json value = literal.is_null() ? spec.default_value : literal;
  json next;
  const bool changed = edit_literal(state, files, id, spec, value, next);
  widgets_[spec.name] = {ImGui::GetItemRectMin(), ImGui::GetItemRectMax()};
  tooltip(spec);
  if (ImGui::IsItemDeactivated()) doc.end_merge();
  if (changed) doc.set_input(id, spec.name, next, "input:" + id + "." + spec.name);
  if (!literal.is_null()) {
    ImGui::TableSetColumnIndex(2);
    if (ImGui::SmallButton("reset")) doc.reset_input(id, spec.name);
    buttons_[spec.name] = {ImGui::GetItemRectMin(), ImGui::GetItemRectMax()};
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("back to the default: %s", spec.default_value.dump().c_str());
  }
}

// The widget the declaration asks for (InputWidget); true with `next` set
// when the user changed the value.
bool PropertyPanel::edit_literal(EditorState& state, FileDialog& files, const std::string& id,
                                 const InputSpec& spec, const json& value, json& next) {
  GraphDocument& doc = state.doc;
  const InputWidget widget = widget_for(spec);
  if (widget == InputWidget::link_only || (value.is_null() && widget != InputWidget::json_text &&
                                           widget != InputWidget::text && widget != InputWidget::file)) {
    ImGui::AlignTextToFramePadding();
    ImGui::TextDisabled("link an input (%s)%s", spec.type->name.c_str(),
                        spec.required() ? ", required" : ", optional");
    return false;
  }
  ImGui::SetNextItemWidth(-FLT_MIN);
  switch (widget) {
    case InputWidget::checkbox: {
      bool b = value.is_boolean() && value.get<bool>();
      return ImGui::Checkbox("##v", &b) && (next = b, true);
    }
    case InputWidget::int_slider:
    case InputWidget::int_drag:
    case InputWidget::number_slider:
    case InputWidget::number_drag: return edit_number(widget, spec, value, next);
    case InputWidget::choice: {
      const std::string current = value.is_string() ? value.get<std::string>() : "";
      bool edited = false;
      if (ImGui::BeginCombo("##v", current.c_str())) {
        for (const auto& choice : spec.choices)
          if (ImGui::Selectable(choice.c_str(), choice == current)) next = choice, edited = true;
        ImGui::EndCombo();
      }
      return edited;
    }
    case InputWidget::text:
    case InputWidget::file: {
      std::string s = value.is_string() ? value.get<std::string>() : "";
      const std::string key = id + "." + spec.name;
      if (widget == InputWidget::file)
        ImGui::SetNextItemWidth(-(ImGui::CalcTextSize("...").x + ImGui::GetStyle().FramePadding.x * 2 +
                                  ImGui::GetStyle().ItemSpacing.x));
      bool edited = ImGui::InputText("##v", &s);
      if (widget == InputWidget::file) {
        const ImVec2 field_min = ImGui::GetItemRectMin();
        ImGui::SameLine();
        const auto base = doc.file().empty() ? std::filesystem::current_path() : doc.file().parent_path();
        if (ImGui::SmallButton("..."))
          files.open("input:" + key, "Choose " + key, s.empty() ? base : base / s,
                     spec.role == InputRole::output_file);
        if (auto chosen = files.take("input:" + key)) {
          std::error_code ec;
          const auto relative = std::filesystem::relative(*chosen, base, ec);
          s = (ec || relative.empty() ? *chosen : relative).string();
          edited = true;
        }
        widgets_[spec.name] = {field_min, ImGui::GetItemRectMax()};
      }
      return edited && (next = s, true);
    }
    case InputWidget::color:
    case InputWidget::int_vector:
    case InputWidget::number_vector: return edit_vector(widget, spec, value, next);
    case InputWidget::json_text: return edit_json_text(id + "." + spec.name, value, next);
    case InputWidget::link_only: break;
  }
  return false;
}

// Lists, point pairs, JSON: edited as text, applied when it parses.
bool PropertyPanel::edit_json_text(const std::string& key, const json& value, json& next) {
  auto it = text_.find(key);
  if (it == text_.end() || !ImGui::IsWindowFocused(ImGuiFocusedFlags_ChildWindows))
    it = text_.insert_or_assign(key, value.is_null() ? std::string() : value.dump()).first;
  ImGui::InputTextMultiline("##json", &it->second, ImVec2(-FLT_MIN, ImGui::GetTextLineHeight() * 4));
  bool changed = false;
  if (ImGui::IsItemDeactivatedAfterEdit()) {
    try {
      next = json::parse(it->second);
      changed = true;
      error_.erase(key);
    } catch (const std::exception& e) {
      error_[key] = e.what();
    }
  }
  if (error_.count(key)) ImGui::TextColored(kError, "not JSON: %s", error_[key].c_str());
  return changed;
}

}  // namespace loom::editor
