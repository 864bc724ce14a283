#include "loom/scene_warnings.hpp"

namespace loom {

namespace {

bool positive(const Eigen::Vector3d& color) { return (color.array() > 0).any(); }

std::string object_name(const SceneObject& o, std::size_t index) {
  return o.name.empty() ? "object " + std::to_string(index) : "object '" + o.name + "'";
}

}  // namespace

bool scene_is_lit(const Scene& scene) {
  for (const Light& l : scene.lights)
    if (l.intensity > 0 && positive(l.color)) return true;
  for (const SceneObject& o : scene.objects)
    if (positive(o.material.emission)) return true;
  return scene.environment.intensity > 0 && !scene.environment.black();
}

std::vector<std::string> scene_warnings(const Scene& scene) {
  std::vector<std::string> warnings;
  if (!scene_is_lit(scene))
    warnings.push_back("nothing lights the scene (no light, no emissive material, a black environment): "
                       "surfaces render black; add a Light, an Environment or a Material with emission");
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& o = scene.objects[i];
    if (!o.mesh || o.mesh->has_uv()) continue;
    std::string maps;
    const auto add = [&maps](bool has, const char* name) {
      if (has) maps += (maps.empty() ? "" : ", ") + std::string(name);
    };
    add(o.material.base_color_map != nullptr, "base-color map");
    add(o.material.normal_map != nullptr, "normal map");
    add(o.material.displacement_map != nullptr && o.material.displacement_scale != 0, "displacement map");
    if (!maps.empty())
      warnings.push_back(object_name(o, i) + ": its mesh has no UVs, so its material's " + maps +
                         " cannot be placed on it; give the mesh UVs (e.g. Parameterize)");
  }
  return warnings;
}

}  // namespace loom
