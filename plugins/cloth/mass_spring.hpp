// A mass-spring system: point masses joined by linear springs, some points
// held fixed. Built from a triangle mesh, a grid cloth or a cuboid lattice.
//
//   X         #V by 3  rest (initial) positions
//   springs   #S by 2  vertex index pairs
//   rest_length, stiffness  #S  per spring (l_s from X, k_s by spring class)
//   mass      #V       lumped masses (density times the area or volume share)
//   fixed     #V       1 for a vertex held at its position, else 0
//   F         #F by 3  triangles for rendering and wind (a cuboid's surface)
//   UV, C     #V by 2, #V by 3  texture coordinates and linear colors carried
//             to every state's mesh (they stay valid as the cloth moves), or empty
#pragma once

#include <vector>

#include <Eigen/Core>

namespace loom::cloth {

struct SpringSystem {
  Eigen::MatrixX3d X;
  Eigen::MatrixX2i springs;
  Eigen::VectorXd rest_length, stiffness;
  Eigen::VectorXd mass;
  Eigen::VectorXi fixed;
  Eigen::MatrixX3i F;
  Eigen::MatrixX2d UV;
  Eigen::MatrixX3d C;

  int vertices() const { return static_cast<int>(X.rows()); }
  int spring_count() const { return static_cast<int>(springs.rows()); }
  int fixed_count() const { return fixed.sum(); }
};

// Springs from a triangle mesh: structural springs on every edge (k_edge) and
// bending springs across each interior edge, joining the two vertices opposite
// it (k_bend; none when k_bend is 0). Masses: area_density times one third of
// each incident triangle's area (a vertex in no triangle gets the mean mass).
SpringSystem mesh_springs(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                          double area_density, double k_edge, double k_bend);

// A grid cloth of nx by ny vertices spanning width x height, vertex (i, j) at
// origin + i·du + j·dv. Structural springs between grid neighbours, shear
// springs on both diagonals of each square, bending springs two vertices
// apart (a class is left out when its k is 0). Row j = ny-1 is the "top".
// UV of vertex (i, j): (i/(nx−1), j/(ny−1)), as GridMesh's.
SpringSystem grid_cloth(int nx, int ny, const Eigen::Vector3d& origin, const Eigen::Vector3d& du,
                        const Eigen::Vector3d& dv, double area_density, double k_structural,
                        double k_shear, double k_bend);
inline int grid_index(int nx, int i, int j) { return j * nx + i; }

// The cuboid lattice of the assignment: nx by ny by nz points filling the box
// [lo, hi], springs along lattice edges (k_edge), face diagonals (k_face) and
// body diagonals (k_body) of every cell. Masses: density times one eighth of
// each incident cell's volume. F is the triangulated surface of the box.
SpringSystem cuboid_lattice(int nx, int ny, int nz, const Eigen::Vector3d& lo,
                            const Eigen::Vector3d& hi, double density, double k_edge, double k_face,
                            double k_body);

// Marks vertices fixed: the listed indices (each checked, the error names the
// index) and every vertex inside the closed box [box_lo, box_hi] (an empty box,
// any box_lo > box_hi, selects nothing).
void fix_vertices(SpringSystem& system, const std::vector<int>& indices,
                  const Eigen::Vector3d& box_lo, const Eigen::Vector3d& box_hi);

// Throws loom::Error naming what is wrong: non-finite or negative masses,
// stiffness or rest lengths, spring indices out of range, a spring joining a
// vertex to itself, zero mass on a free vertex, UVs or colors that do not
// match the vertices or are not finite.
void require_valid(const SpringSystem& system);

// Per-vertex area: one third of each incident triangle's area at positions x.
Eigen::VectorXd vertex_areas(const Eigen::MatrixX3d& x, const Eigen::MatrixX3i& F);

}  // namespace loom::cloth
