// CGAL 5.5's fixed-border parameterizers on a mesh given as V, F, with the
// boundary UVs given (so both sides solve the same system).
#pragma once

#include <string>

#include <Eigen/Core>

namespace loom::bench {

struct CgalPeer;  // a CGAL Surface_mesh built once from V, F

// method: "uniform" (Barycentric_mapping_parameterizer_3), "cotangent"
// (Discrete_conformal_map_parameterizer_3), "mean_value"
// (Mean_value_coordinates_parameterizer_3); solver: "bicgstab" (CGAL's
// default Eigen traits: BiCGSTAB with IncompleteLUT) or "sparselu".
//   V #V by 3, F #F by 3, border_uv #V by 2 (rows of the longest loop used),
//   border_vertex: a vertex of that loop
CgalPeer* cgal_build(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);
void cgal_free(CgalPeer* peer);
// Returns #V by 2 UVs, or throws std::runtime_error naming CGAL's error code.
Eigen::MatrixX2d cgal_parameterize(CgalPeer& peer, const Eigen::MatrixX2d& border_uv, int border_vertex,
                                   const std::string& method, const std::string& solver);

}  // namespace loom::bench
