// Plugin author API. Scene: what both renderers draw: Render (plugin shading, OpenGL through
// OSMesa) and PathTrace (plugin pathtrace, Embree). Nodes assemble it; the
// renderers never keep a scene description of their own.
//
// Conventions (docs/architecture.md): right-handed world, +y up; a camera
// looks down its own -z (OpenGL); colors are linear RGB; angles in radians;
// lengths in scene units; every image here is linear (tag Encoding::linear)
// except normal maps, whose [0, 1] values encode [-1, 1] tangent-space
// vectors (x along +u, y along +v, z along the normal).
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "loom/image.hpp"
#include "loom/mesh.hpp"
#include "loom/point_set.hpp"
#include "loom/polylines.hpp"

namespace loom {

struct Material {
  // How light scatters. The rasterizer shades every model with Blinn-Phong
  // (base_color diffuse, `specular` and `roughness` for the highlight); the
  // path tracer follows the model.
  enum class Model {
    diffuse,     // Lambertian, albedo base_color
    plastic,     // Lambertian base under a dielectric coat of index `ior` (GGX `roughness`)
    conductor,   // GGX microfacet metal, F0 = base_color (Schlick)
    dielectric,  // glass of index `ior`, tinted by base_color; roughness 0 is smooth
  };
  Model model = Model::diffuse;
  Eigen::Vector3d base_color{0.8, 0.8, 0.8};
  std::shared_ptr<const Image> base_color_map;    // multiplies base_color, at the mesh's UVs
  std::shared_ptr<const Image> normal_map;        // tangent space, see the header comment
  std::shared_ptr<const Image> displacement_map;  // height along the normal: channel 0 ...
  double displacement_scale = 0;                  // ... times this, in scene units
  double roughness = 0.5;  // perceptual, [0, 1]; GGX alpha = roughness²
  double specular = 0.5;   // rasterizer only: strength of the Blinn-Phong highlight
  double ior = 1.5;        // plastic coat and dielectric
  Eigen::Vector3d emission{0, 0, 0};  // emitted radiance: an emissive mesh is an area light
};

struct SceneObject {
  std::string name;
  // Exactly one of the three is set.
  std::shared_ptr<const Mesh> mesh;
  std::shared_ptr<const PointSet> points;  // drawn as spheres
  std::shared_ptr<const Polylines> lines;  // drawn as lines (rasterizer only)
  Material material;
  Eigen::Matrix4d transform = Eigen::Matrix4d::Identity();  // object to world
  bool casts_shadow = true;
};

struct Light {
  enum class Kind { point, spot, directional };
  Kind kind = Kind::point;
  Eigen::Vector3d position{0, 5, 0};    // point and spot
  Eigen::Vector3d direction{0, -1, 0};  // spot and directional: where the light shines (unit)
  Eigen::Vector3d color{1, 1, 1};
  // Point and spot: radiant intensity (irradiance intensity / d² at distance d
  // facing the light); directional: irradiance on a surface facing it.
  double intensity = 1;
  double spot_inner = 0.3;  // spot: half-angles; full intensity inside inner,
  double spot_outer = 0.5;  // smoothly down to zero at outer
  bool casts_shadow = true;
};

struct Camera {
  enum class Projection { perspective, orthographic };
  Projection projection = Projection::perspective;
  Eigen::Vector3d eye{0, 0, 5}, target{0, 0, 0}, up{0, 1, 0};
  double fov_y = 0.8;        // perspective: vertical field of view
  double ortho_height = 2;   // orthographic: visible height
  double near_plane = 0.01, far_plane = 1000;
};

// Light arriving from infinitely far away: a lat-long (equirectangular) map of
// radiance, or a uniform color when there is no map; both times intensity.
struct Environment {
  Eigen::Vector3d color{0, 0, 0};
  std::shared_ptr<const Image> map;
  double intensity = 1;
  double rotation = 0;  // about +y

  bool black() const { return !map && (color.array() <= 0).all(); }
};

// The lat-long parameterization, shared by every renderer. For a unit
// direction d: theta = acos(d.y) from +y, phi = atan2(d.x, -d.z);
// u = phi / (2 pi) + 1/2 in [0, 1), v = theta / pi in [0, 1]: the top row of the
// map is straight up, the middle column looks down -z. `rotation` turns the
// map about +y before the lookup (phi - rotation).
inline Eigen::Vector2d latlong_uv(const Eigen::Vector3d& d, double rotation = 0) {
  constexpr double pi = 3.14159265358979323846;
  double u = (std::atan2(d.x(), -d.z()) - rotation) / (2 * pi) + 0.5;
  u -= std::floor(u);
  return {u, std::acos(std::clamp(d.y(), -1.0, 1.0)) / pi};
}
inline Eigen::Vector3d latlong_direction(const Eigen::Vector2d& uv, double rotation = 0) {
  constexpr double pi = 3.14159265358979323846;
  const double phi = (uv.x() - 0.5) * 2 * pi + rotation, theta = uv.y() * pi;
  return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

struct Scene {
  std::vector<SceneObject> objects;
  std::vector<Light> lights;
  std::optional<Camera> camera;  // unset: renderers frame the scene's bounds
  Environment environment;
};

// World-space bounds of every object (empty box for an empty scene).
LOOM_API Eigen::AlignedBox3d bounds(const Scene& scene);
// A camera looking at the scene's bounds from +z (slightly above), fitting it in
// view at the given aspect ratio (width / height).
LOOM_API Camera framing_camera(const Scene& scene, double aspect);
// Throws loom::Error naming the object or light: an object with not exactly
// one geometry, an invalid geometry, a non-finite or singular transform,
// negative colors or intensities, roughness outside [0, 1], ior < 1, a camera
// with NaN or infinite values.
LOOM_API void require_valid(const Scene& scene, const char* what);

template <>
struct TypeTraits<Material> {
  static constexpr const char* name = "Material";
  static constexpr const char* description =
      "how a surface scatters and emits light: model, colors, maps, roughness, ior";
  LOOM_API static std::string summary(const Material& material);
  LOOM_API static void check(const Material& material);
};

template <>
struct TypeTraits<Scene> {
  static constexpr const char* name = "Scene";
  static constexpr const char* description =
      "objects (mesh, points or lines + material + transform), lights, camera, environment";
  LOOM_API static std::string summary(const Scene& scene);
  LOOM_API static void check(const Scene& scene);
};

}  // namespace loom
