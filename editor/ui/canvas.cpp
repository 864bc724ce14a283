#include "canvas.hpp"

#include "canvas_geometry.hpp"
#include "fonts.hpp"
#include "model/auto_layout.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

#include "loom/image.hpp"
#include "loom/mesh.hpp"

namespace loom::editor {

using namespace canvas_geometry;

namespace {



ImU32 status_color(const NodeReport* report, bool running) {
  if (running) return IM_COL32(230, 190, 60, 255);
  if (!report) return IM_COL32(70, 70, 78, 255);
  switch (report->status) {
    case NodeStatus::ran: return IM_COL32(60, 150, 80, 255);
    case NodeStatus::cached: return IM_COL32(60, 110, 170, 255);
    case NodeStatus::failed: return IM_COL32(200, 60, 60, 255);
    case NodeStatus::skipped: return IM_COL32(150, 110, 60, 255);
    case NodeStatus::pruned: return IM_COL32(70, 70, 78, 255);
  }
  return IM_COL32(70, 70, 78, 255);
}

std::string status_text(const NodeReport* report, const LiveNode* live) {
  if (live) return "running " + std::to_string(int(live->progress * 100)) + "%" +
                   (live->label.empty() ? "" : " " + live->label);
  if (!report) return "not evaluated";
  char time[32] = "";
  if (report->status == NodeStatus::ran || report->status == NodeStatus::failed)
    std::snprintf(time, sizeof time, " %.1f ms", report->seconds * 1e3);
  return std::string(to_string(report->status)) + time;
}

// A literal as one short line: numbers and strings as they are, short
// arrays inline, anything long left out (the properties panel shows it).
std::string value_text(const json& v) {
  if (v.is_null() || v.is_object()) return {};
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number_float()) {
    char text[32];
    std::snprintf(text, sizeof text, "%.4g", v.get<double>());
    return text;
  }
  if (v.is_array() && (v.size() > 4 || (!v.empty() && v[0].is_structured()))) return v.empty() ? "[]" : "[...]";
  if (v.is_array()) {
    std::string text = "[";
    for (std::size_t i = 0; i < v.size(); ++i) text += (i ? ", " : "") + value_text(v[i]);
    return text + "]";
  }
  return v.dump();
}

// The text cut with "…" to fit `room` pixels, or empty when nothing fits.
std::string fit_text(ImFont* face, float size, const std::string& text, float room) {
  if (text.empty() || room <= 0) return {};
  if (face->CalcTextSizeA(size, 1e9f, 0, text.c_str()).x <= room) return text;
  const std::string ellipsis = "\u2026";
  std::string cut = text;
  while (!cut.empty()) {
    // Drop one whole UTF-8 character: its continuation bytes, then its lead byte.
    while (!cut.empty() && (static_cast<unsigned char>(cut.back()) & 0xC0) == 0x80) cut.pop_back();
    if (!cut.empty()) cut.pop_back();
    if (!cut.empty() && face->CalcTextSizeA(size, 1e9f, 0, (cut + ellipsis).c_str()).x <= room) return cut + ellipsis;
  }
  return {};
}

// What a node's header says under its id: its type, and a Repeat's body.
std::string type_label(const GraphDocument& doc, const std::string& id) {
  const std::string type = doc.type_name(id);
  if (!doc.is_repeat(id)) return type;
  return "Repeat of " + doc.repeat_body(id);
}

}  // namespace

ImU32 type_color(const TypeInfo& type) {
  if (&type == &type_of<Image>()) return IM_COL32(240, 150, 60, 255);
  if (&type == &type_of<Mesh>()) return IM_COL32(90, 200, 120, 255);
  if (&type == &type_of<double>() || &type == &type_of<int>()) return IM_COL32(170, 170, 180, 255);
  if (&type == &type_of<bool>()) return IM_COL32(220, 100, 100, 255);
  if (is_any(type)) return IM_COL32(255, 255, 255, 255);
  const std::size_t h = std::hash<std::string>{}(type.name);
  float r, g, b;
  ImGui::ColorConvertHSVtoRGB(float(h % 360) / 360.0f, 0.55f, 0.9f, r, g, b);
  return ImGui::ColorConvertFloat4ToU32(ImVec4(r, g, b, 1));
}

ImVec2 Canvas::to_screen(CanvasPoint p) const {
  return origin_ + pan_ + ImVec2(float(p.x), float(p.y)) * zoom_;
}

CanvasPoint Canvas::to_canvas(ImVec2 s) const {
  const ImVec2 c = (s - origin_ - pan_) * (1.0f / zoom_);
  return {c.x, c.y};
}

Canvas::Box Canvas::box(const EditorState& state, const std::string& id) const {
  if (state.doc.collapsed(id)) return {kWidth, kHeader};
  const NodeType* t = state.doc.node_type(id);
  const std::size_t rows = t ? t->spec.outputs.size() + t->spec.inputs.size() : 0;
  float h = kHeader + kRow * float(rows) + kFooter;
  const NodeReport* r = state.report(id);
  if (r && !r->error.empty()) h += kRow * 2;
  auto issue = state.issues.find(id);
  if (issue != state.issues.end()) h += kRow;
  return {kWidth, h};
}

ImVec2 Canvas::node_header(const EditorState& state, const std::string& id) const {
  return to_screen(state.doc.position(id)) + ImVec2(kWidth * 0.5f, kHeader * 0.5f) * zoom_;
}

std::optional<ImVec2> Canvas::output_socket(const EditorState& state, const std::string& id,
                                            const std::string& output) const {
  const NodeType* t = state.doc.node_type(id);
  if (!t) return std::nullopt;
  const int o = t->spec.output_index(output);
  if (o < 0) return std::nullopt;
  const float y = state.doc.collapsed(id) ? kHeader * 0.5f : kHeader + kRow * (float(o) + 0.5f);
  return to_screen(state.doc.position(id)) + ImVec2(kWidth, y) * zoom_;
}

std::optional<ImVec2> Canvas::input_socket(const EditorState& state, const std::string& id,
                                           const std::string& input) const {
  const NodeType* t = state.doc.node_type(id);
  if (!t) return std::nullopt;
  const int i = t->spec.input_index(input);
  if (i < 0) return std::nullopt;
  const float y = state.doc.collapsed(id)
                      ? kHeader * 0.5f
                      : kHeader + kRow * (float(t->spec.outputs.size() + std::size_t(i)) + 0.5f);
  return to_screen(state.doc.position(id)) + ImVec2(0, y) * zoom_;
}

void Canvas::frame_all(const EditorState& state) {
  const auto ids = state.doc.node_ids();
  if (ids.empty() || size_.x <= 0) {
    pan_ = {0, 0};
    zoom_ = 1;
    return;
  }
  float x0 = 1e30f, y0 = 1e30f, x1 = -1e30f, y1 = -1e30f;
  for (const auto& id : ids) {
    const CanvasPoint p = state.doc.position(id);
    const Box b = box(state, id);
    x0 = std::min(x0, float(p.x));
    y0 = std::min(y0, float(p.y));
    x1 = std::max(x1, float(p.x) + b.width);
    y1 = std::max(y1, float(p.y) + b.height);
  }
  const float margin = 30;
  zoom_ = std::clamp(std::min((size_.x - 2 * margin) / (x1 - x0), (size_.y - 2 * margin) / (y1 - y0)), kMinFitZoom,
                     1.25f);
  // Centred when it fits; else from the top left (where the sources are),
  // at a zoom that keeps the labels readable: the rest is a pan away.
  auto place = [&](float view, float lo, float hi) {
    const float extent = (hi - lo) * zoom_;
    return extent <= view - 2 * margin ? (view - extent) * 0.5f - lo * zoom_ : margin - lo * zoom_;
  };
  pan_ = ImVec2(place(size_.x, x0, x1), place(size_.y, y0, y1));
}

CanvasPoint Canvas::free_place(const EditorState& state, CanvasPoint at, const std::string& type) const {
  std::vector<CanvasRect> taken;
  for (const auto& id : state.doc.node_ids()) {
    const CanvasPoint p = state.doc.position(id);
    const Box b = box(state, id);
    taken.push_back({p.x, p.y, b.width, b.height});
  }
  const NodeType* t = state.doc.find_type(type);
  const std::size_t rows = t ? t->spec.outputs.size() + t->spec.inputs.size() : 0;
  return free_spot(taken, at, kWidth, kHeader + kRow * float(rows) + kFooter);
}

std::string Canvas::hit_node(const EditorState& state, ImVec2 s) const {
  const auto ids = state.doc.node_ids();
  for (auto it = ids.rbegin(); it != ids.rend(); ++it) {
    const ImVec2 a = to_screen(state.doc.position(*it));
    const Box b = box(state, *it);
    if (s.x >= a.x && s.y >= a.y && s.x <= a.x + b.width * zoom_ && s.y <= a.y + b.height * zoom_) return *it;
  }
  return {};
}

std::optional<Canvas::SocketHit> Canvas::hit_socket(const EditorState& state, ImVec2 s) const {
  const float reach = std::max(9.0f, kSocket * 1.8f * zoom_);
  for (const auto& id : state.doc.node_ids()) {
    const NodeType* t = state.doc.node_type(id);
    if (!t || state.doc.collapsed(id)) continue;
    for (const auto& o : t->spec.outputs)
      if (distance(*output_socket(state, id, o.name), s) <= reach) return SocketHit{id, o.name, true};
    for (const auto& i : t->spec.inputs)
      if (distance(*input_socket(state, id, i.name), s) <= reach) return SocketHit{id, i.name, false};
  }
  return std::nullopt;
}

void Canvas::draw(EditorState& state) {
  origin_ = ImGui::GetCursorScreenPos();
  size_ = ImGui::GetContentRegionAvail();
  size_.x = std::max(size_.x, 50.0f);
  size_.y = std::max(size_.y, 50.0f);
  if (!framed_once_ || state.level_changed) {
    frame_all(state);
    framed_once_ = true;
    state.level_changed = false;
  }
  // The canvas colour is cleared by the window (EditorApp's backdrops): a
  // full-size rectangle would cost llvmpipe a layer of shading per frame.
  ImDrawList* draw = ImGui::GetWindowDrawList();
  // A grid that pans and zooms with the canvas.
  float step = 40 * zoom_;
  while (step < 20) step *= 5;  // zoomed out: a coarser grid, not a grey wash of lines
  for (float x = std::fmod(pan_.x, step); x < size_.x; x += step)
    draw->AddLine(origin_ + ImVec2(x, 0), origin_ + ImVec2(x, size_.y), IM_COL32(45, 45, 50, 255));
  for (float y = std::fmod(pan_.y, step); y < size_.y; y += step)
    draw->AddLine(origin_ + ImVec2(0, y), origin_ + ImVec2(size_.x, y), IM_COL32(45, 45, 50, 255));

  ImGui::InvisibleButton("canvas", size_,
                         ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight |
                             ImGuiButtonFlags_MouseButtonMiddle);
  draw->PushClipRect(origin_, origin_ + size_, true);
  draw_links(state, draw);
  // Nodes outside the view emit no geometry at all.
  auto visible = [&](const std::string& id) {
    const ImVec2 a = to_screen(state.doc.position(id));
    const Box b = box(state, id);
    return a.x <= origin_.x + size_.x && a.y <= origin_.y + size_.y && a.x + b.width * zoom_ >= origin_.x &&
           a.y + b.height * zoom_ >= origin_.y;
  };
  for (const auto& id : state.doc.node_ids())
    if (!state.selection.count(id) && visible(id)) draw_node(state, draw, id);
  for (const auto& id : state.selection)
    if (state.doc.has_node(id) && visible(id)) draw_node(state, draw, id);
  handle_mouse(state);
  draw->PopClipRect();
  handle_keys(state);
  add_node_menu(state);
}

void Canvas::draw_links(EditorState& state, ImDrawList* draw) {
  const ImVec2 lo = origin_, hi = origin_ + size_;
  auto curve = [&](ImVec2 a, ImVec2 b, ImU32 color, float thickness) {
    const float dx = std::max(40.0f * zoom_, std::abs(b.x - a.x) * 0.5f);
    // The curve lies in the hull of its control points: cull by that box.
    if (std::max(a.x + dx, b.x) < lo.x || std::min(a.x, b.x - dx) > hi.x || std::max(a.y, b.y) < lo.y ||
        std::min(a.y, b.y) > hi.y)
      return;
    // Segments by screen length (a segment every ~10 px, 2..24), not a
    // fixed tessellation: a short link zoomed out is a few triangles.
    const float length = std::abs(b.x - a.x) + std::abs(b.y - a.y) + dx;
    const int segments = std::clamp(int(length / 10), 2, 24);
    draw->AddBezierCubic(a, a + ImVec2(dx, 0), b - ImVec2(dx, 0), b, color, thickness * zoom_, segments);
  };
  for (const auto& id : state.doc.node_ids()) {
    const NodeType* t = state.doc.node_type(id);
    if (!t) continue;
    for (const auto& in : t->spec.inputs) {
      auto l = state.doc.link(id, in.name);
      if (!l || !state.doc.has_node(l->node)) continue;
      auto from = output_socket(state, l->node, l->output);
      auto to = input_socket(state, id, in.name);
      if (from && to) curve(*from, *to, type_color(*in.type), 2.5f);
    }
  }
  if (gesture_ == Gesture::link) {
    const ImVec2 mouse = ImGui::GetIO().MousePos;
    auto anchor = link_from_.output ? output_socket(state, link_from_.node, link_from_.name)
                                    : input_socket(state, link_from_.node, link_from_.name);
    if (anchor) {
      if (link_from_.output)
        curve(*anchor, mouse, IM_COL32(255, 255, 255, 200), 2);
      else
        curve(mouse, *anchor, IM_COL32(255, 255, 255, 200), 2);
    }
  }
}

// An input's value on its row, as Blender shows it in the node: right-aligned
// after the name (`row` is the row's top left on screen), cut to fit.
void Canvas::draw_value(ImDrawList* draw, ImFont* face, float font, ImVec2 row, const InputSpec& in,
                        const json& literal) const {
  const std::string shown = value_text(literal.is_null() ? in.default_value : literal);
  const float name_end = 12 * zoom_ + face->CalcTextSizeA(font, 1e9f, 0, in.name.c_str()).x + 10 * zoom_;
  const std::string fitted = fit_text(face, font, shown, kWidth * zoom_ - 10 * zoom_ - name_end);
  if (fitted.empty()) return;
  const float w = face->CalcTextSizeA(font, 1e9f, 0, fitted.c_str()).x;
  draw->AddText(face, font, row + ImVec2(kWidth * zoom_ - 10 * zoom_ - w, 0),
                literal.is_null() ? IM_COL32(150, 190, 230, 255) : IM_COL32(170, 215, 255, 255), fitted.c_str());
}

// "<- NAME" on the row of an input the group's interface feeds, right-aligned.
void Canvas::draw_group_input(ImDrawList* draw, ImFont* face, float font, ImVec2 row, const std::string& name) const {
  const std::string shown = "\u2190 " + name;
  const float w = face->CalcTextSizeA(font, 1e9f, 0, shown.c_str()).x;
  draw->AddText(face, font, row + ImVec2(kWidth * zoom_ - 10 * zoom_ - w, 0), kGroupColor, shown.c_str());
}

// How a node is drawn at the current zoom.
struct Canvas::NodeLook {
  ImVec2 at;  // top left, screen pixels
  float font;
  ImFont* face;
  // Zoomed far out, labels are unreadable: leave them out (and their
  // triangles, which llvmpipe pays for per frame) and draw plain sockets.
  bool detail;
  int segments;
};

void Canvas::draw_node(EditorState& state, ImDrawList* draw, const std::string& id) {
  const float font = kUiFontSize * zoom_;
  const bool detail = zoom_ >= kLabelZoom;
  const NodeLook look{to_screen(state.doc.position(id)), font, font_for(font), detail, detail ? 0 : 6};
  draw_node_box(state, draw, id, look);
  const NodeType* t = state.doc.node_type(id);
  if (!t) {
    draw->AddText(look.face, font, look.at + ImVec2(8, kHeader + 2) * zoom_, IM_COL32(255, 120, 120, 255),
                  ("unknown type " + state.doc.type_name(id)).c_str());
    return;
  }
  if (state.doc.collapsed(id)) {
    for (const auto& o : t->spec.outputs)
      draw->AddCircleFilled(*output_socket(state, id, o.name), kSocket * zoom_, type_color(*o.type), look.segments);
    return;
  }
  float y = kHeader;
  for (const auto& o : t->spec.outputs) {
    const ImVec2 socket = *output_socket(state, id, o.name);
    draw->AddCircleFilled(socket, kSocket * zoom_, type_color(*o.type), look.segments);
    if (!state.doc.exported_as(id, o.name).empty())  // an output of the group being edited
      draw->AddCircle(socket, kSocket * 1.9f * zoom_, kGroupColor, 0, 2 * zoom_);
    if (detail) {
      const ImVec2 text = look.face->CalcTextSizeA(font, 1e9f, 0, o.name.c_str());
      draw->AddText(look.face, font, look.at + ImVec2(kWidth * zoom_ - text.x - 12 * zoom_, (y + 3) * zoom_),
                    IM_COL32(235, 235, 235, 255), o.name.c_str());
    }
    y += kRow;
  }
  for (const auto& in : t->spec.inputs) {
    draw_input_row(state, draw, id, in, look, y);
    y += kRow;
  }
  draw_node_footer(state, draw, id, look, y);
}

// The box, its header coloured by status, the id and the type under it.
void Canvas::draw_node_box(EditorState& state, ImDrawList* draw, const std::string& id, const NodeLook& look) {
  const ImVec2 a = look.at;
  const Box b = box(state, id);
  const ImVec2 z = ImVec2(b.width, b.height) * zoom_;
  const bool selected = state.selection.count(id) > 0;
  // Rounded corners below a pixel or two are invisible but cost a fan of
  // triangles and an anti-aliased fringe per box.
  const float rounding = zoom_ >= 0.4f ? 5 * zoom_ : 0.0f;
  draw->AddRectFilled(a, a + z, IM_COL32(52, 52, 58, 240), rounding);
  draw->AddRectFilled(a, a + ImVec2(z.x, kHeader * zoom_),
                      status_color(state.report(id), state.live_node(id) != nullptr), rounding,
                      state.doc.collapsed(id) ? ImDrawFlags_RoundCornersAll : ImDrawFlags_RoundCornersTop);
  draw->AddRect(a, a + z, selected ? IM_COL32(255, 220, 120, 255) : IM_COL32(20, 20, 24, 255), rounding, 0,
                selected ? 2.5f : 1.0f);
  // A group node: a band under its header, and "double-click to enter" on hover.
  if (state.doc.is_group_node(id))
    draw->AddRectFilled(a + ImVec2(0, (kHeader - 4) * zoom_), a + ImVec2(z.x, kHeader * zoom_), kGroupColor);
  if (state.viewed == id) draw->AddCircleFilled(a + ImVec2(z.x - 10 * zoom_, 13 * zoom_), 4 * zoom_, IM_COL32_WHITE);
  const std::string title = state.doc.collapsed(id) ? "> " + id : id;
  draw->AddText(look.face, look.font, a + ImVec2(8, 4) * zoom_, IM_COL32_WHITE, title.c_str());
  // The type under the id (a group's file, a Repeat's body), for every kind of node.
  if (look.detail)
    draw->AddText(look.face, look.font * 0.8f, a + ImVec2(8, 22) * zoom_, IM_COL32(225, 225, 230, 255),
                  fit_text(look.face, look.font * 0.8f, type_label(state.doc, id), (kWidth - 16) * zoom_).c_str());
}

// An input's socket (filled when linked or fed by the group's interface), its
// name, its value when it has one, and a red frame when it has an issue.
void Canvas::draw_input_row(EditorState& state, ImDrawList* draw, const std::string& id, const InputSpec& in,
                            const NodeLook& look, float y) {
  const ImVec2 a = look.at;
  const ImVec2 socket = *input_socket(state, id, in.name);
  const std::string promoted = state.doc.promoted_as(id, in.name);  // fed by the group's interface
  const bool linked = state.doc.link(id, in.name).has_value() || !promoted.empty();
  auto node_issues = state.issues.find(id);
  const bool bad = node_issues != state.issues.end() && node_issues->second.count(in.name);
  if (!promoted.empty())
    draw->AddCircleFilled(socket, kSocket * zoom_, kGroupColor, look.segments);
  else if (linked || !look.detail)
    draw->AddCircleFilled(socket, kSocket * zoom_, type_color(*in.type), look.segments);
  else
    draw->AddCircle(socket, kSocket * zoom_, type_color(*in.type), 0, 1.5f * zoom_);
  if (bad)
    draw->AddRect(a + ImVec2(2, y) * zoom_, a + ImVec2(kWidth - 2, y + kRow) * zoom_, IM_COL32(255, 80, 80, 255));
  if (!look.detail) return;
  const json literal = linked ? json() : state.doc.literal(id, in.name);
  draw->AddText(look.face, look.font, a + ImVec2(12, y + 3) * zoom_,
                literal.is_null() ? IM_COL32(215, 215, 215, 255) : IM_COL32(255, 255, 255, 255), in.name.c_str());
  if (!linked) draw_value(draw, look.face, look.font, a + ImVec2(0, (y + 3) * zoom_), in, literal);
  if (!promoted.empty()) draw_group_input(draw, look.face, look.font, a + ImVec2(0, (y + 3) * zoom_), promoted);
}

// The status line, then the node's error and its first validation issue.
void Canvas::draw_node_footer(EditorState& state, ImDrawList* draw, const std::string& id, const NodeLook& look,
                              float y) {
  const NodeReport* report = state.report(id);
  if (look.detail)
    draw->AddText(look.face, look.font * 0.9f, look.at + ImVec2(8, y + 2) * zoom_, IM_COL32(190, 190, 190, 255),
                  status_text(report, state.live_node(id)).c_str());
  y += kFooter;
  if (report && !report->error.empty()) {
    draw->AddText(look.face, look.font * 0.9f, look.at + ImVec2(8, y + 2) * zoom_, IM_COL32(255, 130, 130, 255),
                  report->error.c_str(), nullptr, (kWidth - 16) * zoom_);
    y += 2 * kRow;
  }
  auto node_issues = state.issues.find(id);
  if (node_issues != state.issues.end()) {
    const std::string& first = node_issues->second.begin()->second;
    draw->AddText(look.face, look.font * 0.9f, look.at + ImVec2(8, y + 2) * zoom_, IM_COL32(255, 130, 130, 255),
                  first.c_str(), nullptr, (kWidth - 16) * zoom_);
  }
}

}  // namespace loom::editor
