// The viewport camera: the mouse gestures of a rendered image's viewer as
// moves of a look-at camera (a turntable, as Blender's and Houdini's
// viewports orbit), and the Camera node they are written to.
//
//   orbit: eye turns about the axis `up` through target (yaw), then about the
//          view's right axis (pitch), kept short of the poles
//   pan:   eye and target move together in the image plane, by a fraction
//          of the view's height at the target's distance (the point under the
//          cursor stays under it, for a perspective camera)
//   dolly: eye moves along the view, its distance to target scaled
#pragma once

#include <optional>
#include <string>

#include "loom/builtin_types.hpp"
#include "model/graph_document.hpp"

namespace loom::editor {

struct LookAt {
  Vec3 eye = Vec3(0, 0, 5), target = Vec3(0, 0, 0), up = Vec3(0, 1, 0);
  double fov_degrees = 45;
};

// yaw, pitch in radians; positive yaw moves the eye left about target (the
// scene turns right), positive pitch moves it up.
LookAt orbit(const LookAt& c, double yaw, double pitch);
// dx, dy: fractions of the view's height (positive: the scene moves right, down).
LookAt pan(const LookAt& c, double dx, double dy);
// factor < 1 comes closer.
LookAt dolly(const LookAt& c, double factor);

// The Camera node feeding node `id` through its links at the document's
// level (the nearest one, breadth first), or none.
std::optional<std::string> camera_feeding(const GraphDocument& doc, const std::string& id);
// The camera node's look-at as the graph gives it (literals or defaults);
// none when eye, target or up is linked (the mouse cannot write it).
std::optional<LookAt> camera_inputs(const GraphDocument& doc, const std::string& camera);
// Gives renderer `id` (its "scene" input linked) a Camera node looking as
// `c`: a MergeScenes of the scene it had (a) and the camera (b, which wins)
// feeds it. Three undo steps (the two nodes, two links). Returns the camera's
// id; throws Error when the scene input is not linked.
std::string add_camera(GraphDocument& doc, const std::string& id, const LookAt& c);
// Writes eye and target as one edit, merged with the rest of the gesture.
void write_camera(GraphDocument& doc, const std::string& camera, const LookAt& c, const std::string& merge_key);

}  // namespace loom::editor
