// A mesh as its file stores it (positions, attribute pools, polygons of
// corners) and its conversion to loom::Mesh that keeps the file's vertex list.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "loom/mesh.hpp"

namespace loom::io {

struct IndexedMesh {
  std::vector<Eigen::Vector3d> V;       // positions, in file order
  std::vector<Eigen::Vector3d> C;       // per-vertex colors (empty or #V)
  std::vector<Eigen::Vector2d> UV;      // texture coordinate pool
  std::vector<Eigen::Vector3d> N;       // normal pool
  std::vector<int> polygon_start{0};    // polygon p has corners [start[p], start[p+1])
  std::vector<int> corner_v;            // vertex of each corner
  std::vector<int> corner_uv, corner_n;  // pool index of each corner, or -1 (empty: none)
  int dropped = 0;                      // lines and points skipped
};

struct MeshNotes {
  int split_vertices = 0;  // vertices added where corners at one vertex differ in UV or normal
  int dropped_primitives = 0;
  int degenerate_faces = 0;  // polygons with a repeated vertex, left out
  std::vector<std::string> messages;
};

// Fan-triangulates each polygon and keeps V's order and count: a vertex is
// split (appended at the end) only where its corners carry different UVs or
// normals. UVs/normals are kept when every corner has one. `file` names the
// file in errors.
Mesh to_mesh(const IndexedMesh& m, const std::string& file, MeshNotes* notes);

// Readers of the formats whose indices Loom keeps exactly. Each validates
// counts, indices and numbers and throws loom::Error naming the file and line.
IndexedMesh read_obj_file(const std::string& bytes, const std::string& file);
IndexedMesh read_ply_file(const std::string& bytes, const std::string& file);
IndexedMesh read_off_file(const std::string& bytes, const std::string& file);

// Joins vertices closer than `tolerance` (0: identical positions); faces that
// collapse are removed. Returns the number of vertices merged away.
int weld_vertices(Mesh& mesh, double tolerance);

}  // namespace loom::io
