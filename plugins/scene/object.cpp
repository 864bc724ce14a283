// Object: one mesh, point set or line set with a material and a transform,
// as a one-object scene (MergeScenes combines them).
#include "loom/plugin.hpp"
#include "loom/scene.hpp"
#include "transform.hpp"

namespace {

struct Object {
  static constexpr const char* name = "Object";
  static void declare(loom::NodeSpec& s) {
    s.describe("A one-object scene: a mesh, points or lines (link exactly one) with a material, "
               "placed by scale, then rotation about x, y, z, then translation.")
        .input<loom::Mesh>("mesh", "a triangle mesh").optional()
        .input<loom::PointSet>("points", "points, drawn as spheres").optional()
        .input<loom::Polylines>("lines", "line segments").optional()
        .input<loom::Material>("material", "the material (default: diffuse gray)").optional()
        .input<loom::Vec3>("translate", loom::Vec3(0, 0, 0), "position offset")
        .input<loom::Vec3>("rotate_degrees", loom::Vec3(0, 0, 0),
                           "rotation about x, then y, then z, in degrees")
        .input<loom::Vec3>("scale", loom::Vec3(1, 1, 1), "scale per axis (non-zero)")
        .input<std::string>("name", std::string(), "a name for messages and renderer outputs")
        .input<bool>("casts_shadow", true, "whether the object shadows others")
        .output<loom::Scene>("scene", "a scene holding this one object");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    loom::SceneObject o;
    o.name = in.get<std::string>("name");
    const int given = int(in.has("mesh")) + int(in.has("points")) + int(in.has("lines"));
    if (given != 1)
      throw loom::Error("link exactly one of mesh, points or lines (" + std::to_string(given) +
                        " given)");
    if (in.has("mesh")) {
      o.mesh = in.share<loom::Mesh>("mesh");
      loom::require_valid(*o.mesh, "mesh");
    } else if (in.has("points")) {
      o.points = in.share<loom::PointSet>("points");
      loom::require_valid(*o.points, "points");
    } else {
      o.lines = in.share<loom::Polylines>("lines");
      loom::require_valid(*o.lines, "lines");
    }
    if (in.has("material")) o.material = in.get<loom::Material>("material");
    o.transform = loom::scene::object_transform(in.get<loom::Vec3>("translate"),
                                                in.get<loom::Vec3>("rotate_degrees"),
                                                in.get<loom::Vec3>("scale"));
    o.casts_shadow = in.get<bool>("casts_shadow");
    loom::Scene scene;
    scene.objects.push_back(std::move(o));
    out.set("scene", std::move(scene));
  }
};
LOOM_NODE(Object);

}  // namespace
