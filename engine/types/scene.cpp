#include "loom/scene.hpp"

#include <sstream>

namespace loom {

namespace {

template <class M>
void extend(Eigen::AlignedBox3d& box, const M& P, const Eigen::Matrix4d& T, double pad = 0) {
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    const Eigen::Vector3d p = (T * P.row(i).transpose().homogeneous()).hnormalized();
    box.extend(p + Eigen::Vector3d::Constant(pad));
    box.extend(p - Eigen::Vector3d::Constant(pad));
  }
}

void require_valid_material(const Material& m, const std::string& on) {
  if (!m.base_color.allFinite() || (m.base_color.array() < 0).any())
    throw Error(on + ": base color must be finite and non-negative");
  if (!m.emission.allFinite() || (m.emission.array() < 0).any())
    throw Error(on + ": emission must be finite and non-negative");
  if (!(m.roughness >= 0 && m.roughness <= 1)) throw Error(on + ": roughness must be in [0, 1]");
  if (!(m.ior >= 1 && std::isfinite(m.ior))) throw Error(on + ": ior must be at least 1");
  if (!std::isfinite(m.displacement_scale)) throw Error(on + ": displacement scale is not finite");
}

std::string object_name(const SceneObject& o, std::size_t i) {
  return "object " + std::to_string(i) + (o.name.empty() ? "" : " (" + o.name + ")");
}

}  // namespace

Eigen::AlignedBox3d bounds(const Scene& scene) {
  Eigen::AlignedBox3d box;
  for (const SceneObject& o : scene.objects) {
    if (o.mesh) extend(box, o.mesh->V, o.transform);
    if (o.lines) extend(box, o.lines->P, o.transform);
    if (o.points) {
      const double pad = o.points->has_radius() ? o.points->radius.maxCoeff() : 0;
      extend(box, o.points->P, o.transform, pad);
    }
  }
  return box;
}

Camera framing_camera(const Scene& scene, double aspect) {
  Camera camera;
  const Eigen::AlignedBox3d box = bounds(scene);
  if (box.isEmpty()) return camera;
  const Eigen::Vector3d center = box.center();
  const double radius = std::max(0.5 * box.diagonal().norm(), 1e-6);
  // The bounding sphere fits the narrower of the two fields of view.
  const double half_fov = 0.5 * camera.fov_y * std::min(1.0, aspect);
  const double distance = radius / std::sin(half_fov);
  const Eigen::Vector3d dir = Eigen::Vector3d(0, 0.35, 1).normalized();
  camera.target = center;
  camera.eye = center + distance * dir;
  camera.near_plane = std::max(distance - radius, distance * 1e-3) * 0.5;
  camera.far_plane = (distance + radius) * 2;
  camera.ortho_height = 2 * radius;
  return camera;
}

void require_valid(const Scene& scene, const char* what) {
  const std::string name = what;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& o = scene.objects[i];
    const std::string on = name + ": " + object_name(o, i);
    if (int(bool(o.mesh)) + int(bool(o.points)) + int(bool(o.lines)) != 1)
      throw Error(on + " must hold exactly one of a mesh, points or lines");
    if (o.mesh) require_valid(*o.mesh, on.c_str());
    if (o.points) require_valid(*o.points, on.c_str());
    if (o.lines) require_valid(*o.lines, on.c_str());
    if (!o.transform.allFinite() || std::abs(o.transform.topLeftCorner<3, 3>().determinant()) < 1e-300)
      throw Error(on + " has a non-finite or singular transform");
    require_valid_material(o.material, on);
  }
  for (std::size_t i = 0; i < scene.lights.size(); ++i) {
    const Light& l = scene.lights[i];
    const std::string ln = name + ": light " + std::to_string(i);
    if (!l.position.allFinite() || !l.direction.allFinite() || !l.color.allFinite() ||
        !std::isfinite(l.intensity))
      throw Error(ln + " has NaN or infinite values");
    if ((l.color.array() < 0).any() || l.intensity < 0)
      throw Error(ln + " has a negative color or intensity");
    if (l.kind != Light::Kind::point && l.direction.norm() < 1e-12)
      throw Error(ln + " has no direction");
  }
  if (const auto& c = scene.camera;
      c && (!c->eye.allFinite() || !c->target.allFinite() || !c->up.allFinite() || !std::isfinite(c->fov_y) ||
            !std::isfinite(c->ortho_height) || !std::isfinite(c->near_plane) || !std::isfinite(c->far_plane)))
    throw Error(name + ": the camera has NaN or infinite values");
  const Environment& env = scene.environment;
  if (!env.color.allFinite() || (env.color.array() < 0).any() || !(env.intensity >= 0) ||
      !std::isfinite(env.intensity))
    throw Error(name + ": the environment's color and intensity must be finite and non-negative");
}

void TypeTraits<Material>::check(const Material& m) { require_valid_material(m, "the material"); }
void TypeTraits<Scene>::check(const Scene& scene) { require_valid(scene, "the scene"); }

std::string TypeTraits<Material>::summary(const Material& m) {
  static const char* const models[] = {"diffuse", "plastic", "conductor", "dielectric"};
  std::ostringstream s;
  s << "Material " << models[static_cast<int>(m.model)] << " base (" << m.base_color.transpose()
    << ") roughness " << m.roughness;
  if (m.base_color_map) s << ", color map";
  if (m.normal_map) s << ", normal map";
  if (m.displacement_map) s << ", displacement map";
  if ((m.emission.array() > 0).any()) s << ", emissive";
  return s.str();
}

std::string TypeTraits<Scene>::summary(const Scene& scene) {
  std::ostringstream s;
  s << "Scene " << scene.objects.size() << " objects, " << scene.lights.size() << " lights";
  if (scene.camera) s << ", camera";
  if (scene.environment.map)
    s << ", environment " << scene.environment.map->width() << "x" << scene.environment.map->height();
  else if (!scene.environment.black())
    s << ", uniform environment";
  return s.str();
}

}  // namespace loom
