// Plugin author API. Mesh: a triangle mesh as Eigen matrices, in the libigl style.
//   V  #V by 3  vertex positions
//   F  #F by 3  vertex indices of each triangle, counter-clockwise seen from outside
//   UV #V by 2  per-vertex texture coordinates in [0,1]², or empty
//   N  #V by 3  per-vertex unit normals, or empty
//   C  #V by 3  per-vertex linear RGB colors, or empty
#pragma once

#include <Eigen/Core>

#include "loom/value.hpp"

namespace loom {

struct Mesh {
  Eigen::MatrixX3d V;
  Eigen::MatrixX3i F;
  Eigen::MatrixX2d UV;
  Eigen::MatrixX3d N;
  Eigen::MatrixX3d C;

  int vertices() const { return static_cast<int>(V.rows()); }
  int faces() const { return static_cast<int>(F.rows()); }
  bool has_uv() const { return UV.rows() == V.rows() && V.rows() > 0; }
  bool has_normals() const { return N.rows() == V.rows() && V.rows() > 0; }
  bool has_colors() const { return C.rows() == V.rows() && V.rows() > 0; }
};

// Throws loom::Error on indices out of range, non-finite positions or
// attribute rows that do not match the vertex count ("what" names the mesh).
LOOM_API void require_valid(const Mesh& mesh, const char* what);

template <>
struct TypeTraits<Mesh> {
  static constexpr const char* name = "Mesh";
  static constexpr const char* description =
      "triangle mesh: V #V×3, F #F×3, optional per-vertex UV, normals, colors";
  LOOM_API static std::string summary(const Mesh& mesh);
  static constexpr int version = 1;
  LOOM_API static void write(const Mesh& v, ByteWriter& w);
  LOOM_API static Mesh read(ByteReader& r);
  LOOM_API static std::size_t bytes(const Mesh& v);
  LOOM_API static void check(const Mesh& v);
};

}  // namespace loom
