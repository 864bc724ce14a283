// Displacement mapping for the path tracer, done on the geometry before the
// BVH build (Render does the same on the GPU by tessellation):
//   1. uniform subdivision, `level` times: each triangle into four at its edge
//      midpoints (shared edges share their midpoint: no cracks), positions,
//      UVs, normals and colors interpolated linearly;
//   2. every vertex moved along its unit normal (the mesh's normals, or area
//      weighted ones when it has none) by h(uv) · scale, h the map's first
//      channel sampled bilinearly (texture.hpp, Render's convention);
//   3. normals recomputed from the displaced triangles.
#pragma once

#include "loom/image.hpp"
#include "loom/mesh.hpp"

namespace loom::pathtrace {

// One level of midpoint subdivision (4 triangles per triangle).
Mesh subdivide_midpoint(const Mesh& mesh);

// mesh with UVs; level >= 0 (0: displace the vertices as they are).
Mesh displaced_mesh(const Mesh& mesh, const Image& map, double scale, int level);

}  // namespace loom::pathtrace
