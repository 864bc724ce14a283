// GLSL 4.50 sources of the rasterizer's programs (see shader_sources.cpp).
#pragma once

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
