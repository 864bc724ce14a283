// MPM particles in D = 2 or 3 dimensions, structure of arrays.
//   x, v    #P positions and velocities (domain units, seconds)
//   C       #P APIC/MLS affine velocity matrices (Jiang et al. 2015)
//   F       #P deformation gradients (solids, snow, sand)
//   J       #P volume ratio: fluid's det F; snow's plastic Jp (hardening)
//   q       #P sand's accumulated plastic (Hencky) strain, the hardening
//           state of Klár et al. 2016 §7.3; 0 at the start, unused otherwise
//   material, mu, lambda, mass, volume: per-particle constants
//   color   #P linear RGB
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace loom::mpm {

enum class Material : std::uint8_t { fluid = 0, elastic = 1, snow = 2, sand = 3 };

// Lamé parameters from Young's modulus and Poisson's ratio. For the fluid,
// E is the bulk modulus K of the J-based pressure (mpm88's "E") and ν is unused.
struct Lame {
  double mu, lambda;
};
Lame lame_parameters(Material material, double E, double nu);

template <int D>
struct Particles {
  using Vec = Eigen::Matrix<double, D, 1>;
  using Mat = Eigen::Matrix<double, D, D>;

  std::vector<Vec> x, v;
  std::vector<Mat> C, F;
  std::vector<double> J, q;
  std::vector<Material> material;
  std::vector<double> mu, lambda, mass, volume;
  std::vector<Eigen::Vector3f> color;

  int size() const { return static_cast<int>(x.size()); }
  // Calls f(&Particles::array) for every per-particle array, in the order above
  // (the order MPMState stores them in): the one list of them that reserving,
  // appending, storing and reordering go through.
  template <typename F>
  static void each_array(const F& f) {
    f(&Particles::x), f(&Particles::v), f(&Particles::C), f(&Particles::F), f(&Particles::J), f(&Particles::q);
    f(&Particles::material), f(&Particles::mu), f(&Particles::lambda), f(&Particles::mass), f(&Particles::volume);
    f(&Particles::color);
  }
  void reserve(std::size_t n);
  // Appends one particle at rest state (F = I, C = 0, J = 1, q = 0).
  void add(const Vec& position, const Vec& velocity, Material m, const Lame& lame, double mass,
           double volume, const Eigen::Vector3f& color);
  void append(const Particles& other);
};

}  // namespace loom::mpm
