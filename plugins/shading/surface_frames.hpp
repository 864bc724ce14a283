// Per-vertex frames for shading: normals and the tangents dP/du, dP/dv that
// normal mapping (tangent space) and displacement mapping (the displaced
// surface's normal) need.
#pragma once

#include <Eigen/Core>

namespace loom::shading {

// Area-weighted vertex normals (sum of the faces' cross products), unit
// length; a vertex of no non-degenerate face gets +z.
//   V #V by 3, F #F by 3  ->  #V by 3
Eigen::MatrixX3d vertex_normals(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);

// Per-vertex surface derivatives from the UVs (Lengyel 2001): on each face,
// [dP/du dP/dv] = [e1 e2] [du1 du2; dv1 dv2]^-1, summed over the vertex's faces
// weighted by the face's 3D area; faces with a degenerate UV triangle add
// nothing. The lengths are kept (scene units per unit of UV): the displaced
// surface's normal needs them; normal mapping orthonormalizes them against the
// normal (Gram-Schmidt) in the shader.
//   V #V by 3, F #F by 3, UV #V by 2  ->  dPdu, dPdv #V by 3
void uv_tangents(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const Eigen::MatrixX2d& UV,
                 Eigen::MatrixX3d& dPdu, Eigen::MatrixX3d& dPdv);

}  // namespace loom::shading
