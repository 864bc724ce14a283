// Plugin author API. Per-vertex frames for shading: normals and the tangents dP/du, dP/dv that
// normal mapping (tangent space) and displacement mapping (the displaced
// surface's normal) need. Used by both renderers: Render (plugin shading)
// uploads them to its shaders, PathTrace (plugin pathtrace) interpolates them
// at ray hits.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "loom/export.hpp"

namespace loom::numerics {

// Area-weighted vertex normals (sum of the faces' cross products), unit
// length; a vertex of no non-degenerate face gets +z.
//   V #V by 3, F #F by 3  ->  #V by 3
LOOM_API Eigen::MatrixX3d vertex_normals(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);

// Per-vertex surface derivatives from the UVs (Lengyel 2001): on each face,
// [dP/du dP/dv] = [e1 e2] [du1 du2; dv1 dv2]^-1, summed over the vertex's faces
// weighted by the face's 3D area; faces with a degenerate UV triangle add
// nothing. The lengths are kept (scene units per unit of UV): the displaced
// surface's normal needs them; normal mapping orthonormalizes them against the
// normal (tangent_basis below, or the same Gram-Schmidt in Render's shader).
//   V #V by 3, F #F by 3, UV #V by 2  ->  dPdu, dPdv #V by 3
LOOM_API void uv_tangents(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                          const Eigen::MatrixX2d& UV, Eigen::MatrixX3d& dPdu, Eigen::MatrixX3d& dPdv);

// The orthonormal tangent frame of normal mapping at a point with unit normal
// n: T = dP/du minus its part along n, normalized (Gram-Schmidt); B = n x T,
// turned to the side of dP/dv (the UV map's handedness). Returns false, and
// leaves T and B alone, when dP/du is (nearly) parallel to n or zero.
// A tangent-space vector m (x along +u, y along +v, z along n) is
// m.x T + m.y B + m.z n in world space.
template <class Vec3>
bool tangent_basis(const Vec3& n, const Vec3& dpdu, const Vec3& dpdv, Vec3* T, Vec3* B) {
  const Vec3 t = dpdu - n * n.dot(dpdu);
  const auto length = t.norm();
  if (!(length > 1e-5 * dpdu.norm())) return false;
  *T = t / length;
  *B = n.cross(*T);
  if (B->dot(dpdv) < 0) *B = -*B;
  return true;
}

}  // namespace loom::numerics
