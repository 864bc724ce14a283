// Plugin author API. Polylines: line sets (trajectories, springs, wireframes).
//   P  #P by 3  vertex positions
//   E  #E by 2  segments as pairs of vertex indices
//   C  #P by 3  per-vertex linear RGB colors, or empty
// A strip of n points is n-1 segments; Render draws them as lines.
#pragma once

#include <Eigen/Core>

#include "loom/value.hpp"

namespace loom {

struct Polylines {
  Eigen::MatrixX3d P;
  Eigen::MatrixX2i E;
  Eigen::MatrixX3d C;

  int vertices() const { return static_cast<int>(P.rows()); }
  int segments() const { return static_cast<int>(E.rows()); }
  bool has_colors() const { return C.rows() == P.rows() && P.rows() > 0; }
};

// Throws loom::Error on non-finite positions, indices out of range or color
// rows that do not match the vertex count.
LOOM_API void require_valid(const Polylines& lines, const char* what);

template <>
struct TypeTraits<Polylines> {
  static constexpr const char* name = "Polylines";
  static constexpr const char* description =
      "line segments: P #P×3 vertices, E #E×2 index pairs, optional per-vertex colors";
  LOOM_API static std::string summary(const Polylines& lines);
  static constexpr int version = 1;
  LOOM_API static void write(const Polylines& v, ByteWriter& w);
  LOOM_API static Polylines read(ByteReader& r);
  LOOM_API static std::size_t bytes(const Polylines& v);
  LOOM_API static void check(const Polylines& v);
};

}  // namespace loom
