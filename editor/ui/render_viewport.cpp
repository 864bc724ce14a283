#include "render_viewport.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <imgui.h>

#include "loom/image.hpp"
#include "loom/scene.hpp"

namespace loom::editor {

namespace {

constexpr double kOrbitPerPixel = 0.01;  // radians: a 300-pixel drag turns ~170°
constexpr double kDollyPerNotch = 0.85;

}  // namespace

bool RenderViewport::applies(const EditorState& state, const std::string& id) {
  const NodeType* t = state.doc.node_type(id);
  if (!t) return false;
  const InputSpec* scene = t->spec.find_input("scene");
  bool image = false;
  for (const auto& o : t->spec.outputs) image |= o.type == &type_of<Image>();
  return image && scene && scene->type == &type_of<Scene>();
}

std::optional<Partial> RenderViewport::newest_pass(const EditorState& state, const EvaluationController& controller,
                                                   const std::string& id, const std::string& output) {
  std::optional<Partial> p = controller.partial(state.engine_id(id), output);
  if (!p || (state.eval && state.eval->revision > p->revision)) return std::nullopt;
  return p;
}

std::string RenderViewport::status(const Partial& p) {
  char text[128];
  int n = std::snprintf(text, sizeof text, "%.4g/%.0f %s, %.2f s", p.done, p.total, p.unit.c_str(), p.seconds);
  if (p.relative_error >= 0) std::snprintf(text + n, sizeof text - n, ", ±%.1f %%", 100 * p.relative_error);
  return text;
}

bool RenderViewport::toolbar(EditorState& state, const std::string& id) {
  camera_ = camera_feeding(state.doc, id);
  look_ = camera_ ? camera_inputs(state.doc, *camera_) : std::nullopt;
  if (!camera_) {
    ImGui::TextDisabled("no Camera node feeds this scene");
    ImGui::SameLine();
    if (state.doc.link(id, "scene") && ImGui::SmallButton("add a Camera node")) add_camera_from_scene(state, id);
    return false;
  }
  if (!look_) {
    ImGui::TextDisabled("camera %s: its eye, target or up is linked, so the mouse cannot move it", camera_->c_str());
    return false;
  }
  ImGui::Checkbox("camera", &enabled_);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("on the image: drag orbits, right or middle drag pans, wheel dollies (%s)", camera_->c_str());
  return enabled_;
}

// The new Camera node looks as the scene's own camera did (CornellBox's),
// so the image does not jump.
void RenderViewport::add_camera_from_scene(EditorState& state, const std::string& id) {
  LookAt c;
  const Value scene = state.upstream_value(id, "scene");
  if (scene && scene.is<Scene>() && scene.as<Scene>().camera) {
    const Camera& camera = *scene.as<Scene>().camera;
    c.eye = camera.eye;
    c.target = camera.target;
    c.up = camera.up;
    c.fov_degrees = camera.fov_y * 180 / M_PI;
  }
  add_camera(state.doc, id, c);
}

void RenderViewport::draw(EditorState& state, const std::string&, const ImageView& view) {
  if (!enabled_ || !camera_ || !look_ || view.scale <= 0) return;
  const ImGuiIO& io = ImGui::GetIO();
  const double height = std::max(1.0f, view.height * view.scale);  // the image's height on screen
  std::optional<LookAt> moved;
  if (view.active && (io.MouseDelta.x != 0 || io.MouseDelta.y != 0)) {
    if (ImGui::IsMouseDown(ImGuiMouseButton_Left))  // the scene turns with the mouse, as if held
      moved = orbit(*look_, io.MouseDelta.x * kOrbitPerPixel, io.MouseDelta.y * kOrbitPerPixel);
    else if (ImGui::IsMouseDown(ImGuiMouseButton_Right) || ImGui::IsMouseDown(ImGuiMouseButton_Middle))
      moved = pan(*look_, io.MouseDelta.x / height, io.MouseDelta.y / height);
  } else if (view.hovered && io.MouseWheel != 0) {
    moved = dolly(*look_, std::pow(kDollyPerNotch, io.MouseWheel));
  }
  if (moved) {
    write_camera(state.doc, *camera_, *moved, view.active ? "viewport-drag" : "viewport-wheel");
    dragging_ = view.active;
  } else if (dragging_ && !view.active) {
    state.doc.end_merge();  // the drag ended: one undo step
    dragging_ = false;
  }
}

}  // namespace loom::editor
