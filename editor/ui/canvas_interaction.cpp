// The canvas's mouse and keyboard: selection, moving, linking (refused with
// a reason), box selection, pan and zoom, shortcuts and the add-node menu.
#include <algorithm>
#include <cctype>
#include <set>

#include <GLFW/glfw3.h>

#include "canvas.hpp"
#include "canvas_geometry.hpp"
#include "model/node_search.hpp"

namespace loom::editor {

using namespace canvas_geometry;

// One frame of the mouse over the canvas: the wheel zooms, hovering explains,
// a press starts a gesture (move, link, box, pan) that later frames continue.
void Canvas::handle_mouse(EditorState& state) {
  const ImVec2 mouse = ImGui::GetIO().MousePos;
  if (ImGui::IsItemHovered()) {
    zoom_at(mouse);
    if (gesture_ == Gesture::none) explain_hovered(state, mouse);
    if (ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left)) {
      if (std::string id = hit_node(state, mouse); !id.empty() && state.doc.is_group_node(id)) {
        gesture_ = Gesture::none;
        state.enter(id);
        return;
      }
    }
    begin_gesture(state, mouse);
  }
  switch (gesture_) {
    case Gesture::move:
      continue_move(state, mouse);
      break;
    case Gesture::link:
      continue_link(state, mouse);
      break;
    case Gesture::box:
      continue_box(state, mouse);
      break;
    case Gesture::pan:
      continue_pan(mouse);
      break;
    case Gesture::none:
      break;
  }
  if (!refusal_.empty() && ImGui::GetTime() < refusal_until_) ImGui::SetTooltip("link refused: %s", refusal_.c_str());
}

// The wheel zooms about the point under the mouse.
void Canvas::zoom_at(ImVec2 mouse) {
  const float wheel = ImGui::GetIO().MouseWheel;
  if (wheel == 0) return;
  const CanvasPoint before = to_canvas(mouse);
  zoom_ = std::clamp(zoom_ * std::pow(1.15f, wheel), 0.1f, 3.0f);
  pan_ = mouse - origin_ - ImVec2(float(before.x), float(before.y)) * zoom_;
}

// Hovering a node or an input shows its description or its error.
void Canvas::explain_hovered(EditorState& state, ImVec2 mouse) {
  GraphDocument& doc = state.doc;
  if (auto s = hit_socket(state, mouse)) {
    const NodeType* t = doc.node_type(s->node);
    if (s->output) {
      const auto& o = t->spec.outputs[std::size_t(t->spec.output_index(s->name))];
      ImGui::SetTooltip("%s (%s)\n%s", o.name.c_str(), o.type->name.c_str(), o.description.c_str());
    } else {
      const InputSpec* in = t->spec.find_input(s->name);
      std::string issue;
      auto ni = state.issues.find(s->node);
      if (ni != state.issues.end() && ni->second.count(s->name)) issue = "\n" + ni->second.at(s->name);
      ImGui::SetTooltip("%s (%s)\n%s%s", in->name.c_str(), in->type->name.c_str(), in->description.c_str(),
                        issue.c_str());
    }
  } else if (std::string id = hit_node(state, mouse); !id.empty()) {
    const NodeReport* r = state.report(id);
    if (r && !r->error.empty())
      ImGui::SetTooltip("%s", r->error.c_str());
    else if (doc.is_repeat(id))
      ImGui::SetTooltip("Repeat: double-click to enter its body");
    else if (doc.is_group_node(id))
      ImGui::SetTooltip("group %s: double-click to enter it", doc.type_name(id).c_str());
  }
}

// A left press on a socket starts a link (or picks up the one at an input),
// on a node's arrow folds it, on a node selects and starts moving, elsewhere
// starts a box selection; a right or middle press starts panning.
void Canvas::begin_gesture(EditorState& state, ImVec2 mouse) {
  if (ImGui::IsMouseClicked(ImGuiMouseButton_Left)) begin_left_press(state, mouse);
  if (ImGui::IsMouseClicked(ImGuiMouseButton_Right) || ImGui::IsMouseClicked(ImGuiMouseButton_Middle)) {
    press_ = mouse;
    gesture_ = Gesture::pan;
  }
}

void Canvas::begin_left_press(EditorState& state, ImVec2 mouse) {
  GraphDocument& doc = state.doc;
  const ImGuiIO& io = ImGui::GetIO();
  press_ = mouse;
  if (auto s = hit_socket(state, mouse)) {
    gesture_ = Gesture::link;
    link_from_ = *s;
    if (!s->output)
      if (auto l = doc.link(s->node, s->name)) {
        // Picking up an existing link: it leaves its input and follows the mouse.
        doc.disconnect(s->node, s->name);
        link_from_ = {l->node, l->output, true};
      }
  } else if (std::string id = hit_node(state, mouse); !id.empty()) {
    const ImVec2 a = to_screen(doc.position(id));
    if (mouse.y < a.y + kHeader * zoom_ && mouse.x < a.x + 20 * zoom_) {
      doc.set_collapsed(id, !doc.collapsed(id));
      return;
    }
    if (io.KeyCtrl || io.KeyShift) {
      if (!state.selection.erase(id)) state.selection.insert(id);
    } else if (!state.selection.count(id)) {
      state.selection = {id};
    }
    state.viewed = id;
    gesture_ = Gesture::move;
    drag_last_ = to_canvas(mouse);
  } else {
    gesture_ = Gesture::box;
    if (!io.KeyCtrl && !io.KeyShift) state.selection.clear();
  }
}

void Canvas::continue_move(EditorState& state, ImVec2 mouse) {
  if (!ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
    state.doc.end_merge();
    gesture_ = Gesture::none;
    return;
  }
  const CanvasPoint now = to_canvas(mouse);
  const std::vector<std::string> ids(state.selection.begin(), state.selection.end());
  state.doc.move_nodes(ids, now.x - drag_last_.x, now.y - drag_last_.y, "move");
  drag_last_ = now;
}

// A link follows the mouse; over a socket it fits (green) or is refused with
// the reason (red); released, it connects or shows the refusal.
void Canvas::continue_link(EditorState& state, ImVec2 mouse) {
  GraphDocument& doc = state.doc;
  auto target = hit_socket(state, mouse);
  std::string reason;
  bool fits = false;
  if (target && target->output != link_from_.output) {
    const SocketHit& out = link_from_.output ? link_from_ : *target;
    const SocketHit& in = link_from_.output ? *target : link_from_;
    reason = doc.link_refusal(out.node, out.name, in.node, in.name);
    fits = reason.empty();
    if (!fits) ImGui::SetTooltip("%s", reason.c_str());
    auto where = in.output ? std::nullopt : input_socket(state, in.node, in.name);
    if (where)
      ImGui::GetWindowDrawList()->AddCircle(*where, kSocket * 2 * zoom_,
                                            fits ? IM_COL32(120, 255, 120, 255) : IM_COL32(255, 80, 80, 255), 0, 2);
  }
  if (ImGui::IsMouseDown(ImGuiMouseButton_Left)) return;
  if (fits) {
    const SocketHit& out = link_from_.output ? link_from_ : *target;
    const SocketHit& in = link_from_.output ? *target : link_from_;
    doc.connect(out.node, out.name, in.node, in.name);
  } else if (!reason.empty()) {
    refusal_ = reason;
    refusal_until_ = ImGui::GetTime() + 2.5;
  }
  gesture_ = Gesture::none;
}

void Canvas::continue_box(EditorState& state, ImVec2 mouse) {
  const ImVec2 lo(std::min(press_.x, mouse.x), std::min(press_.y, mouse.y));
  const ImVec2 hi(std::max(press_.x, mouse.x), std::max(press_.y, mouse.y));
  ImGui::GetWindowDrawList()->AddRectFilled(lo, hi, IM_COL32(120, 160, 255, 40));
  ImGui::GetWindowDrawList()->AddRect(lo, hi, IM_COL32(120, 160, 255, 200));
  if (ImGui::IsMouseDown(ImGuiMouseButton_Left)) return;
  for (const auto& id : state.doc.node_ids()) {
    const ImVec2 a = to_screen(state.doc.position(id));
    const Box b = box(state, id);
    if (a.x >= lo.x && a.y >= lo.y && a.x + b.width * zoom_ <= hi.x && a.y + b.height * zoom_ <= hi.y)
      state.selection.insert(id);
  }
  gesture_ = Gesture::none;
}

void Canvas::continue_pan(ImVec2 mouse) {
  if (ImGui::IsMouseDown(ImGuiMouseButton_Right) || ImGui::IsMouseDown(ImGuiMouseButton_Middle)) {
    pan_ = pan_ + ImGui::GetIO().MouseDelta;
    return;
  }
  // A right click that did not move opens the add-node menu.
  if (distance(mouse, press_) < 4) {
    menu_at_ = to_canvas(mouse);
    menu_filter_.clear();
    menu_focus_ = true;
    ImGui::OpenPopup("add node");
  }
  gesture_ = Gesture::none;
}

// Wherever the mouse is (canvas, properties, viewer), unless a text field
// is being edited.
void Canvas::handle_keys(EditorState& state) {
  ImGuiIO& io = ImGui::GetIO();
  if (io.WantTextInput || ImGui::IsPopupOpen("", ImGuiPopupFlags_AnyPopupId)) return;
  GraphDocument& doc = state.doc;
  const std::vector<std::string> selected(state.selection.begin(), state.selection.end());
  if (ImGui::IsKeyPressed(GLFW_KEY_DELETE) || ImGui::IsKeyPressed(GLFW_KEY_BACKSPACE)) {
    doc.remove_nodes(selected);
    state.selection.clear();
  }
  if (io.KeyCtrl && ImGui::IsKeyPressed(GLFW_KEY_D) && !selected.empty()) {
    auto added = doc.duplicate(selected);
    state.selection = {added.begin(), added.end()};
  }
  try {
    if (io.KeyCtrl && !io.KeyShift && ImGui::IsKeyPressed(GLFW_KEY_G) && !selected.empty())
      state.selection = {doc.group(selected)};
    if (io.KeyCtrl && io.KeyShift && ImGui::IsKeyPressed(GLFW_KEY_G)) ungroup_selection(state);
  } catch (const std::exception& e) {
    refusal_ = e.what();
    refusal_until_ = ImGui::GetTime() + 3;
  }
  if (io.KeyCtrl && ImGui::IsKeyPressed(GLFW_KEY_C) && !selected.empty())
    ImGui::SetClipboardText(doc.copy(selected).dump(1).c_str());
  if (io.KeyCtrl && ImGui::IsKeyPressed(GLFW_KEY_V)) {
    const char* text = ImGui::GetClipboardText();
    try {
      const CanvasPoint at = to_canvas(io.MousePos);
      json clip = json::parse(text ? text : "");
      // Paste at the mouse: shift so the clip's first node lands there.
      double dx = 40, dy = 40;
      if (clip.contains("nodes") && clip["nodes"].is_object() && !clip["nodes"].empty()) {
        const json& first = clip["nodes"].begin().value();
        if (first.contains("ui") && first["ui"].contains("pos")) {
          dx = at.x - first["ui"]["pos"][0].get<double>();
          dy = at.y - first["ui"]["pos"][1].get<double>();
        }
      }
      auto added = doc.paste(clip, dx, dy);
      state.selection = {added.begin(), added.end()};
    } catch (const std::exception& e) {
      refusal_ = std::string("the clipboard holds no graph: ") + e.what();
      refusal_until_ = ImGui::GetTime() + 3;
    }
  }
  if (ImGui::IsKeyPressed(GLFW_KEY_F) && !io.KeyCtrl) frame_all(state);
  if (ImGui::IsKeyPressed(GLFW_KEY_TAB)) {
    // Over the canvas the new node goes to the mouse, else to the view's middle.
    const bool over = ImGui::IsWindowHovered();
    menu_at_ = to_canvas(over ? io.MousePos : origin_ + size_ * 0.5f);
    if (!over) ImGui::SetNextWindowPos(origin_ + size_ * 0.5f);
    menu_filter_.clear();
    menu_focus_ = true;
    ImGui::OpenPopup("add node");
  }
}

// Every selected group node replaced by its inner nodes (selected then).
void ungroup_selection(EditorState& state) {
  std::set<std::string> added;
  for (const auto& id : state.selection)
    if (state.doc.has_node(id) && state.doc.is_group_node(id) && !state.doc.is_repeat(id))
      for (const auto& inner : state.doc.ungroup(id)) added.insert(inner);
  if (!added.empty()) state.selection = added;
}

void Canvas::add_node_menu(EditorState& state) {
  menu_open_ = ImGui::BeginPopup("add node");
  if (!menu_open_) return;
  if (menu_focus_) {
    ImGui::SetKeyboardFocusHere();
    menu_focus_ = false;
  }
  if (menu_focus_) state.doc.rescan_group_files();  // the library may have changed
  char buffer[128];
  std::snprintf(buffer, sizeof buffer, "%s", menu_filter_.c_str());
  const bool enter = ImGui::InputTextWithHint("##filter", "search node types", buffer, sizeof buffer,
                                              ImGuiInputTextFlags_EnterReturnsTrue);
  menu_filter_ = buffer;
  std::string chosen;
  int shown = 0;
  std::vector<const NodeType*> types = state.doc.registry().all();
  for (const NodeType* g : state.doc.group_types()) types.push_back(g);
  for (const NodeType* t : search_node_types(types, menu_filter_)) {
    const NodeSpec& s = t->spec;
    if (enter && shown == 0) chosen = s.name;
    ++shown;
    if (ImGui::Selectable((s.name + "  [" + s.plugin + "]").c_str())) chosen = s.name;
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", s.description.c_str());
  }
  if (shown == 0) ImGui::TextDisabled("no node type matches");
  if (!chosen.empty()) {
    try {
      const std::string id = state.doc.add_node(chosen, free_place(state, menu_at_, chosen));
      state.selection = {id};
      state.viewed = id;
    } catch (const std::exception& e) {
      refusal_ = e.what();
      refusal_until_ = ImGui::GetTime() + 3;
    }
    ImGui::CloseCurrentPopup();
    // No text field keeps the keyboard: shortcuts work at once.
    ImGui::SetWindowFocus(nullptr);
  }
  ImGui::EndPopup();
}

}  // namespace loom::editor
