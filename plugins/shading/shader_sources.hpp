// GLSL 4.50 sources of the rasterizer's programs (see shader_sources.cpp).
#pragma once

#include "gl_program.hpp"

namespace loom::shading {

// What the programs assume: at most 8 lights, 4 of them with shadow maps, and
// these texture units (samplers of different types never share a unit).
constexpr int max_lights = 8, max_shadows = 4;
constexpr GLuint unit_base = 0, unit_normal = 1, unit_displacement = 2, unit_shadow = 4, unit_cube = 8;
constexpr GLuint texture_units_used = 12;
// Points every sampler uniform of `p` at its unit.
void bind_sampler_units(GlProgram& p);

}  // namespace loom::shading

namespace loom::shading::glsl {

extern const char* const mesh_vertex;         // object -> world, frame attributes
extern const char* const mesh_tess_control;   // uniform tessellation level
extern const char* const mesh_tess_eval;      // displacement along the interpolated normal
extern const char* const mesh_fragment;       // Blinn-Phong, normal and displacement maps, shadows
extern const char* const depth_fragment;      // shadow maps: the light's depth metric
extern const char* const sphere_vertex;       // point sets as sphere impostors
extern const char* const sphere_geometry;
extern const char* const sphere_fragment;
extern const char* const line_vertex;         // polylines and the wireframe overlay
extern const char* const line_fragment;

}  // namespace loom::shading::glsl
