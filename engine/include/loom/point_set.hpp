// Plugin author API. PointSet: particles and point clouds, in the libigl style.
//   P  #P by 3  positions (2D simulations write z = 0)
//   radius  #P  per-point radius, or empty (the consumer's default radius)
//   C  #P by 3  per-point linear RGB colors, or empty
//   attributes  named per-point values, each #P by k (k = 1 a scalar such
//               as mass, k = 3 a vector such as velocity); SavePoints writes
//               them as PLY properties (name, or name_x name_y name_z)
// Render draws a PointSet as shaded spheres; SavePoints (plugin io) writes it
// as a PLY point cloud. A simulation keeps its own state type and outputs a PointSet
// to be drawn or saved.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "loom/value.hpp"

namespace loom {

struct PointAttribute {
  std::string name;
  Eigen::MatrixXd values;  // #P by k, 1 <= k <= 3
};

struct PointSet {
  Eigen::MatrixX3d P;
  Eigen::VectorXd radius;
  Eigen::MatrixX3d C;
  std::vector<PointAttribute> attributes;

  int points() const { return static_cast<int>(P.rows()); }
  bool has_radius() const { return radius.size() == P.rows() && P.rows() > 0; }
  bool has_colors() const { return C.rows() == P.rows() && P.rows() > 0; }
};

// Throws loom::Error on non-finite positions, negative radii, attribute
// rows that do not match the point count, non-finite attribute values, or an
// attribute without a name, with 0 or more than 3 columns, or named twice
// ("what" names the point set).
LOOM_API void require_valid(const PointSet& points, const char* what);

template <>
struct TypeTraits<PointSet> {
  static constexpr const char* name = "PointSet";
  static constexpr const char* description =
      "points: P #P×3, optional per-point radius, linear RGB colors and named attributes";
  LOOM_API static std::string summary(const PointSet& points);
  static constexpr int version = 2;  // 2: named attributes
  LOOM_API static void write(const PointSet& v, ByteWriter& w);
  LOOM_API static PointSet read(ByteReader& r);
  LOOM_API static std::size_t bytes(const PointSet& v);
  LOOM_API static void check(const PointSet& v);
};

}  // namespace loom
