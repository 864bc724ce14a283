// GLSL 4.50 sources of the rasterizer's programs (see shader_sources.cpp).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "gl_program.hpp"
#include "rasterizer.hpp"

namespace loom::shading {

// The texture units the programs use (samplers of different types never share a unit).
constexpr GLuint unit_base = 0, unit_normal = 1, unit_displacement = 2, unit_environment = 3, unit_shadow = 4,
                 unit_cube = 8;
constexpr GLuint texture_units_used = 12;
// Points every sampler uniform of `p` at its unit.
void bind_sampler_units(GlProgram& p);

// What a lighting program is compiled for. llvmpipe executes both sides of
// every branch under a mask, so features switched off by uniforms still cost
// their full price per fragment: each feature set gets its own program.
struct LightingVariant {
  std::vector<std::pair<Light::Kind, int>> lights;  // per light: its kind and shadow slot, or -1
  ShadowFilter shadow_filter = ShadowFilter::off;   // off when no light has a shadow map
  int pcf_size = 1;
  bool environment_map = false;  // SH irradiance + prefiltered reflections, else u_ambient
};
// The variant as GLSL #define lines (also the key of the compiled program):
// the limits (MAX_LIGHTS, MAX_SHADOWS), every light kind's and shadow
// filter's code by name (LIGHT_POINT, ..., FILTER_PCSS: the one mapping the
// GLSL compares against), SHADOW_FILTER, PCF_SIZE, ENV_MAP and LIGHTS.
std::string lighting_defines(const LightingVariant& v);

}  // namespace loom::shading

namespace loom::shading::glsl {

extern const char* const mesh_vertex;         // object -> world, frame attributes
extern const char* const mesh_tess_control;   // uniform tessellation level
extern const char* const mesh_tess_eval;      // displacement along the interpolated normal
// Blinn-Phong, normal and displacement maps, shadows. `defines`: lighting_defines
// plus HAS_BASE_MAP, HAS_NORMAL_MAP, HAS_DISPLACEMENT, HAS_VERTEX_COLOR (0 or 1).
std::string mesh_fragment(const std::string& defines);
extern const char* const empty_fragment;      // depth only
extern const char* const depth_fragment;      // shadow maps: the light's depth metric
extern const char* const sphere_vertex;       // point sets as sphere impostors
extern const char* const sphere_geometry;
// lighting_defines plus DEPTH_PASS (1: the shadow pass's depth metric only).
std::string sphere_fragment(const std::string& defines);
// The environment map behind everything (a full-viewport triangle).
extern const char* const background_vertex;
std::string background_fragment();
extern const char* const line_vertex;         // polylines and the wireframe overlay
extern const char* const line_fragment;

}  // namespace loom::shading::glsl
