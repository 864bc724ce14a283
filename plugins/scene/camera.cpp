// Camera: a perspective or orthographic look-at camera as a scene holding
// only the camera.
#include <cmath>

#include "loom/plugin.hpp"
#include "loom/scene.hpp"
#include "transform.hpp"

namespace {

struct CameraNode {
  static constexpr const char* name = "Camera";
  static void declare(loom::NodeSpec& s) {
    s.describe("A scene holding only a camera, looking from eye at target; merge it with objects.")
        .enum_input("projection", loom::Camera::Projection::perspective,
                    {{loom::Camera::Projection::perspective, "perspective"},
                     {loom::Camera::Projection::orthographic, "orthographic"}},
                    "the projection")
        .input<loom::Vec3>("eye", loom::Vec3(0, 0, 5), "where the camera is")
        .input<loom::Vec3>("target", loom::Vec3(0, 0, 0), "the point it looks at")
        .input<loom::Vec3>("up", loom::Vec3(0, 1, 0), "which way is up (not along the view)")
        .input<double>("fov_degrees", 45.0, "perspective: vertical field of view")
        .range(0.1, 179)
        .input<double>("ortho_height", 2.0, "orthographic: visible height in scene units")
        .range(1e-9, 1e12)
        .input<double>("near", 0.01, "near clipping distance (rasterizer)")
        .range(1e-9, 1e12)
        .input<double>("far", 1000.0, "far clipping distance (rasterizer)")
        .range(1e-9, 1e12)
        .output<loom::Scene>("scene", "a scene holding the camera");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    loom::Camera c;
    c.projection = in.get<loom::Camera::Projection>("projection");
    c.eye = in.get<loom::Vec3>("eye");
    c.target = in.get<loom::Vec3>("target");
    if (!c.eye.allFinite() || !c.target.allFinite()) throw loom::Error("eye and target must be finite");
    const Eigen::Vector3d view = loom::scene::unit(c.target - c.eye, "target - eye");
    c.up = loom::scene::unit(in.get<loom::Vec3>("up"), "up");
    if (std::abs(view.dot(c.up)) > 1 - 1e-9) throw loom::Error("up must not point along the view");
    c.fov_y = loom::scene::radians(in.get<double>("fov_degrees"));
    c.ortho_height = in.get<double>("ortho_height");
    c.near_plane = in.get<double>("near");
    c.far_plane = in.get<double>("far");
    if (c.near_plane >= c.far_plane) throw loom::Error("near must be less than far");
    loom::Scene scene;
    scene.camera = c;
    out.set("scene", std::move(scene));
  }
};
LOOM_NODE(CameraNode);

}  // namespace
