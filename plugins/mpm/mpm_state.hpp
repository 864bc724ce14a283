// The MPM simulation state as a Loom value ("MPMState"): the particles of a 2D
// or a 3D simulation, the simulated time and the last frame's substep count.
// Storable in the disk cache (write/read), so simulated frames persist.
#pragma once

#include <string>

#include "loom/point_set.hpp"
#include "loom/serialize.hpp"
#include "loom/value.hpp"
#include "particles.hpp"

namespace loom::mpm {

struct MpmState {
  int dim = 2;  // which of p2 / p3 holds the particles
  Particles<2> p2;
  Particles<3> p3;
  double time = 0;    // seconds simulated since the initial state
  int substeps = 0;   // substeps of the last advance

  int size() const { return dim == 2 ? p2.size() : p3.size(); }
};

// Positions (z = 0 in 2D), a constant radius and the particles' colours.
PointSet point_set(const MpmState& state, double radius);

// point_set with the particles' numbers as attributes: velocity (m/s, z = 0
// in 2D), mass (kg), volume (rest volume), J (volume ratio: the fluid's J,
// det F of a solid, det F · Jp of snow), snow_plastic_J (Jp, 1 for the
// other materials), plastic_strain (sand's q, 0 otherwise) and material
// (0 fluid, 1 elastic, 2 snow, 3 sand).
PointSet particle_points(const MpmState& state, double radius);

}  // namespace loom::mpm

template <>
struct loom::TypeTraits<loom::mpm::MpmState> {
  static constexpr const char* name = "MPMState";
  static constexpr const char* description =
      "MPM particles (2D or 3D): positions, velocities, affine C, F, J, material, colour";
  static constexpr int version = 2;  // 2: sand's hardening state q
  static std::string summary(const loom::mpm::MpmState& s);
  // Throws when a particle's position, velocity or deformation is NaN or
  // infinite: the step diverged.
  static void check(const loom::mpm::MpmState& s);
  static void write(const loom::mpm::MpmState& s, loom::ByteWriter& w);
  static loom::mpm::MpmState read(loom::ByteReader& r);
};
