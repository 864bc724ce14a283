// Back-face culling that cannot change the image. Seen from a point outside
// a closed, consistently oriented surface, every ray that meets it meets a
// front face first (it enters the solid), so the back faces are always
// hidden behind front faces of the same mesh: the depth test would discard
// them, but llvmpipe would still set up, rasterize and shade them (0.42 of
// the target frame's main pass, docs/shading.md). A clipping near plane
// breaks the argument (it opens the solid), so the mesh must lie beyond it.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace loom::shading {

// +1 when every connected part of the mesh is closed and oriented outward
// (each edge shared by exactly two faces that run it in opposite directions,
// positive signed volume), -1 when every part is closed and oriented inward,
// 0 otherwise (open, non-manifold, inconsistent, flat or mixed). Positions
// within 1e-6 of the mesh's extent are one vertex (a UV seam's duplicates);
// faces that collapse to an edge or point cover no pixel and are skipped.
// V: #V by 3 positions, F: #F by 3 indices.
int closed_orientation(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);

// The side of a closed mesh (orientation as above) that can never be seen
// through this view: GL_BACK (+1), GL_FRONT (-1: faces wound inward, or
// outward under a mirroring model matrix), or 0 (cull nothing) when the mesh
// is not closed or its bounds (object space) reach the near plane
// (view-space z = -near_plane: the camera looks down -z).
unsigned hidden_side(int orientation, const Eigen::AlignedBox3d& bounds, const Eigen::Matrix4d& model,
                     const Eigen::Matrix4d& view, double near_plane);

}  // namespace loom::shading
