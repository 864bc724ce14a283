#include "model/viewport_camera.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <set>

#include <Eigen/Geometry>

#include "loom/error.hpp"

namespace loom::editor {

LookAt orbit(const LookAt& c, double yaw, double pitch) {
  const Vec3 up = c.up.normalized();
  Vec3 offset = c.eye - c.target;
  offset = Eigen::AngleAxisd(-yaw, up) * offset;
  // Pitch about the right axis, kept 1° short of the poles: past them the
  // look-at's up would flip the image.
  const double r = offset.norm();
  const double elevation = std::asin(std::clamp(offset.normalized().dot(up), -1.0, 1.0));
  const double limit = M_PI / 2 - M_PI / 180;
  const double turn = std::clamp(elevation + pitch, -limit, limit) - elevation;
  const Vec3 right = up.cross(offset).normalized();
  offset = Eigen::AngleAxisd(-turn, right) * offset;
  LookAt out = c;
  out.eye = c.target + offset.normalized() * r;
  return out;
}

LookAt pan(const LookAt& c, double dx, double dy) {
  const Vec3 view = c.target - c.eye;
  const Vec3 right = view.cross(c.up).normalized();
  const Vec3 up = right.cross(view).normalized();
  // The view's height at the target's distance: 2 d tan(fov/2).
  const double height = 2 * view.norm() * std::tan(c.fov_degrees * M_PI / 360);
  const Vec3 move = (-dx * right + dy * up) * height;
  LookAt out = c;
  out.eye += move;
  out.target += move;
  return out;
}

LookAt dolly(const LookAt& c, double factor) {
  LookAt out = c;
  out.eye = c.target + (c.eye - c.target) * factor;
  return out;
}

std::optional<std::string> camera_feeding(const GraphDocument& doc, const std::string& id) {
  std::deque<std::string> queue{id};
  std::set<std::string> seen{id};
  while (!queue.empty()) {
    const std::string node = queue.front();
    queue.pop_front();
    if (node != id && doc.type_name(node) == "Camera") return node;
    const NodeType* type = doc.node_type(node);
    if (!type) continue;
    for (const InputSpec& input : type->spec.inputs)
      if (auto l = doc.link(node, input.name); l && doc.has_node(l->node) && seen.insert(l->node).second)
        queue.push_back(l->node);
  }
  return std::nullopt;
}

std::optional<LookAt> camera_inputs(const GraphDocument& doc, const std::string& camera) {
  const NodeType* type = doc.node_type(camera);
  if (!type) return std::nullopt;
  auto value = [&](const std::string& name) -> std::optional<json> {
    if (doc.link(camera, name)) return std::nullopt;
    json v = doc.literal(camera, name);
    if (v.is_null()) v = type->spec.find_input(name)->default_value;
    return v;
  };
  LookAt c;
  auto vec = [](const json& j) { return Vec3(j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()); };
  const auto eye = value("eye"), target = value("target"), up = value("up"), fov = value("fov_degrees");
  if (!eye || !target || !up) return std::nullopt;
  c.eye = vec(*eye);
  c.target = vec(*target);
  c.up = vec(*up);
  if (fov) c.fov_degrees = fov->get<double>();
  return c;
}

std::string add_camera(GraphDocument& doc, const std::string& id, const LookAt& c) {
  const auto scene = doc.link(id, "scene");
  if (!scene) throw Error("the scene of " + id + " is not linked: there is no scene to add a camera to");
  auto j = [](const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); };
  const CanvasPoint at = doc.position(id);
  const json clip = {
      {"loom", 1},
      {"nodes",
       {{"camera", {{"type", "Camera"},
                    {"inputs", {{"eye", j(c.eye)}, {"target", j(c.target)}, {"up", j(c.up)},
                                {"fov_degrees", c.fov_degrees}}},
                    {"ui", {{"pos", {at.x - 480, at.y + 160}}}}}},
        {"camera_merge", {{"type", "MergeScenes"},
                          {"inputs", {{"b", {{"from", "camera.scene"}}}}},
                          {"ui", {{"pos", {at.x - 240, at.y + 80}}}}}}}}};
  const std::vector<std::string> added = doc.paste(clip, 0, 0);  // in key order: camera, camera_merge
  for (const std::string& refused :
       {doc.connect(scene->node, scene->output, added.at(1), "a"), doc.connect(added.at(1), "scene", id, "scene")})
    if (!refused.empty()) throw Error(refused);
  return added.at(0);
}

void write_camera(GraphDocument& doc, const std::string& camera, const LookAt& c, const std::string& merge_key) {
  auto j = [](const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); };
  doc.set_inputs(camera, {{"eye", j(c.eye)}, {"target", j(c.target)}}, merge_key);
}

}  // namespace loom::editor
