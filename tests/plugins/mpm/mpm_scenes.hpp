// Small MPM scenes shared by the tests (and the benchmark includes it too).
#pragma once

#include "emitters.hpp"
#include "mls_mpm.hpp"

namespace loom::mpm::test {

// A block of `material` filling [lo, hi]^D at `spacing`, jittered, seeded.
template <int D>
Particles<D> block(double lo, double hi, Material material, double E, double spacing,
                   std::uint64_t seed = 1) {
  EmitOptions o;
  o.material = material;
  o.E = E;
  o.nu = 0.2;
  o.spacing = spacing;
  o.seed = seed;
  using Vec = Eigen::Matrix<double, D, 1>;
  return fill_shape<D>([](const Vec&) { return true; }, Vec::Constant(lo), Vec::Constant(hi), o);
}

// mpm88: 8,192 fluid particles in [0.2, 0.6]², 128², E = 400, p_vol = (Δx/2)².
inline Particles<2> mpm88(int count = 8192, std::uint64_t seed = 1) {
  EmitOptions o;
  o.material = Material::fluid;
  o.E = 400;
  o.sampling = Sampling::random;
  o.count = count;
  o.particle_volume = (0.5 / 128) * (0.5 / 128);
  o.seed = seed;
  return fill_shape<2>([](const Eigen::Vector2d&) { return true; }, Eigen::Vector2d(0.2, 0.2),
                       Eigen::Vector2d(0.6, 0.6), o);
}

template <int D>
Eigen::Matrix<double, D, 1> momentum(const Particles<D>& ps) {
  Eigen::Matrix<double, D, 1> p = Eigen::Matrix<double, D, 1>::Zero();
  for (int i = 0; i < ps.size(); ++i) p += ps.mass[i] * ps.v[i];
  return p;
}

}  // namespace loom::mpm::test
