// The shadow-map pass: one map per shadow-casting light (up to max_shadows),
// each storing a linear depth metric in scene units in an R32F texture (2D
// for spot lights, a cube for point lights), or for directional lights the
// depth buffer itself (linear along the light: metric = near + depth01 (far -
// near)), bound to its texture unit for the image pass.
#pragma once

#include <vector>

#include "gl_program.hpp"
#include "gpu_scene.hpp"
#include "rasterizer.hpp"
#include "view_math.hpp"

namespace loom::shading {

struct ShadowMap {
  int light = -1;  // index in scene.lights
  ShadowView view;
  GLuint color = 0, depth = 0, fbo = 0;  // color: the sampled map (the depth texture if ortho)
};

struct DepthPrograms {
  GlProgram& mesh;
  GlProgram& depth_only;  // no fragment output: orthographic maps keep the depth buffer
  GlProgram& tessellated;
  GlProgram& spheres;
};

// The maps of one render, deleted with it (also when the render throws).
class ShadowMaps {
 public:
  explicit ShadowMaps(const GlApi& gl) : gl_(gl) {}
  ~ShadowMaps();
  ShadowMaps(const ShadowMaps&) = delete;
  ShadowMaps& operator=(const ShadowMaps&) = delete;

  std::vector<ShadowMap> maps;

 private:
  const GlApi& gl_;
};

// Renders the maps into `out` and binds map i to unit_shadow + i (2D) or unit_cube + i.
void render_shadow_maps(const GlApi& gl, const DepthPrograms& programs, const GpuScene& gpu, const Scene& scene,
                        const Eigen::AlignedBox3d& box, const RenderOptions& options, ShadowMaps& out);

}  // namespace loom::shading
