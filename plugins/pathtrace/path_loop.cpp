#include "path_loop.hpp"

#include <algorithm>

namespace loom::pathtrace {

namespace {

// The scene's materials as the path loop reads them, per traced object.
std::vector<ObjectShading> object_shading(const Scene& scene, const EmbreeScene& traced) {
  std::vector<ObjectShading> shading(traced.objects().size());
  for (std::size_t i = 0; i < shading.size(); ++i) {
    const Material& mat = scene.objects[traced.objects()[i].scene_index].material;
    ObjectShading& sh = shading[i];
    sh.material.model = mat.model;
    sh.material.base = mat.base_color.cast<float>();
    const float rough = float(std::clamp(mat.roughness, 0.0, 1.0));
    sh.material.ggx.alpha = rough * rough;
    sh.material.ior = float(std::max(mat.ior, 1.0));
    if (mat.base_color_map && !mat.base_color_map->empty()) sh.base_color_map = mat.base_color_map.get();
    if (mat.normal_map && !mat.normal_map->empty() && !traced.objects()[i].dPdu.empty())
      sh.normal_map = mat.normal_map.get();
    sh.reflective_only = mat.model != Material::Model::dielectric;
    sh.emission = mat.emission.cast<float>();
    sh.emissive = (sh.emission.array() > 0).any();
    sh.lambert = mat.model == Material::Model::diffuse;
  }
  return shading;
}

std::vector<Vec3f> emission_of(const std::vector<ObjectShading>& shading) {
  std::vector<Vec3f> emission;
  for (const ObjectShading& sh : shading) emission.push_back(sh.emission);
  return emission;
}

}  // namespace

PathScene::PathScene(const Scene& scene, const EmbreeScene& traced_scene,
                     EnvironmentLight::Sampling environment_sampling)
    : traced(traced_scene),
      shading(object_shading(scene, traced_scene)),
      environment(scene.environment, environment_sampling),
      lights(scene, traced_scene, emission_of(shading), environment),
      emitters_hittable(!environment.black() || std::any_of(shading.begin(), shading.end(),
                                                            [](const ObjectShading& sh) { return sh.emissive; })) {}

PathResult trace_path(const PathContext& c, Vec3f origin, Vec3f dir, PixelSampler& sampler) {
  const Strategies use = strategies(c);
  PathResult r;
  PathVertex v;
  v.dir = dir;
  v.prev_point = origin;
  SurfaceHit hit;
  for (int depth = 0;; ++depth) {
    ++r.rays;
    sampler.start_bounce(depth, use.nee && c.lights.reads_point());
    if (!c.traced.intersect(origin, v.dir, kInf, &hit, depth == 0)) {
      add_environment(c, v, use, depth, r);
      break;
    }
    float wo_side;
    const Vec3f base = arrive(c, use, v, depth, hit, r, wo_side);
    if (depth >= c.settings.max_depth) break;
    if (!scatter(c, hit, wo_side, c.shading[std::size_t(hit.object)], base, use, sampler, v, r)) break;
    if (!next_ray(c, hit, depth, sampler, v, origin)) break;
  }
  return r;
}

}  // namespace loom::pathtrace
