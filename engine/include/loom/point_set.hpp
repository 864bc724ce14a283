// PointSet: particles and point clouds, in the libigl style.
//   P  #P by 3  positions (2D simulations write z = 0)
//   radius  #P  per-point radius, or empty (the consumer's default radius)
//   C  #P by 3  per-point linear RGB colors, or empty
// Render draws a PointSet as shaded spheres; SavePoints (plugin io) writes it
// as a PLY point cloud. A simulation keeps its own state type and outputs a PointSet
// to be drawn or saved.
#pragma once

#include <Eigen/Core>

#include "loom/value.hpp"

namespace loom {

struct PointSet {
  Eigen::MatrixX3d P;
  Eigen::VectorXd radius;
  Eigen::MatrixX3d C;

  int points() const { return static_cast<int>(P.rows()); }
  bool has_radius() const { return radius.size() == P.rows() && P.rows() > 0; }
  bool has_colors() const { return C.rows() == P.rows() && P.rows() > 0; }
};

// Throws loom::Error on non-finite positions, negative radii or attribute
// rows that do not match the point count ("what" names the point set).
LOOM_API void require_valid(const PointSet& points, const char* what);

template <>
struct TypeTraits<PointSet> {
  static constexpr const char* name = "PointSet";
  static constexpr const char* description =
      "points: P #P×3, optional per-point radius and linear RGB colors";
  LOOM_API static std::string summary(const PointSet& points);
  static constexpr int version = 1;
  LOOM_API static void write(const PointSet& v, ByteWriter& w);
  LOOM_API static PointSet read(ByteReader& r);
  LOOM_API static std::size_t bytes(const PointSet& v);
  LOOM_API static void check(const PointSet& v);
};

}  // namespace loom
