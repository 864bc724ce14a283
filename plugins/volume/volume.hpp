// Volume: sparse grids on one voxel lattice, as OpenVDB keeps them: a density
// (mass per volume, kg/m³ for an MPM state in metres) and, when the points had
// velocities, a velocity vector grid. Voxel (i, j, k) is centred at
// (i, j, k)·voxel_size, as OpenVDB's linear transform and MPM's grid nodes
// put it, so a voxel is an MPM grid node when voxel_size = Δx.
#pragma once

#include <string>

#include <openvdb/openvdb.h>

#include "loom/value.hpp"

namespace loom::volume {

struct Volume {
  double voxel_size = 0;
  openvdb::FloatGrid::ConstPtr density;   // grid "density", a fog volume
  openvdb::Vec3SGrid::ConstPtr velocity;  // grid "velocity" (m/s), or null
};

}  // namespace loom::volume

template <>
struct loom::TypeTraits<loom::volume::Volume> {
  static constexpr const char* name = "Volume";
  static constexpr const char* description =
      "sparse OpenVDB grids on one voxel lattice: density, and velocity when the points had it";
  static std::string summary(const loom::volume::Volume& v);
};
