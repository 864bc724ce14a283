// ClothState as a Loom value type: the state a ClothStep maps from frame f−1 to
// frame f (positions, velocities, simulated time and the system they belong
// to), storable in the persistent cache.
#pragma once

#include <string>

#include "loom/mesh.hpp"
#include "loom/point_set.hpp"
#include "loom/value.hpp"
#include "time_step.hpp"

namespace loom::cloth {

// The deformed surface of a state: its positions with the system's
// triangles, UVs and colors.
Mesh state_mesh(const ClothState& state);

// The state as points: positions, the system's colors, and the attributes
// "velocity" (m/s), "mass" (kg) and "fixed" (1 held, 0 free).
PointSet state_points(const ClothState& state);

}  // namespace loom::cloth

namespace loom {

template <>
struct TypeTraits<cloth::ClothState> {
  static constexpr const char* name = "ClothState";
  static constexpr const char* description =
      "a mass-spring system (springs, masses, fixed vertices) with its positions, velocities "
      "and simulated time";
  static constexpr int version = 2;  // 2: the system's UVs and colors
  static std::string summary(const cloth::ClothState& s);
  // Throws when a position or velocity is NaN or infinite: the step diverged.
  static void check(const cloth::ClothState& s);
  static void write(const cloth::ClothState& s, ByteWriter& w);
  static cloth::ClothState read(ByteReader& r);
};

}  // namespace loom
