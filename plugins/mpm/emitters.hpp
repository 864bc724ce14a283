// Filling shapes with particles: box, disk/sphere and the inside of a closed
// triangle mesh, by a regular, jittered or Poisson-disk (Bridson 2007) sampling
// at a given spacing, or `count` uniformly random points (mpm88's sampling).
#pragma once

#include <cstdint>
#include <functional>

#include <Eigen/Core>

#include "particles.hpp"

namespace loom::mpm {

enum class Sampling { grid, jittered, poisson, random };

struct EmitOptions {
  Material material = Material::elastic;
  double E = 1e4, nu = 0.2, density = 1;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3f color = Eigen::Vector3f::Ones();
  Sampling sampling = Sampling::jittered;
  double spacing = 1.0 / 256;  // grid, jittered, poisson: distance between particles
  int count = 0;                // random: number of particles
  // Per-particle volume; 0: the shape's volume (estimated at `spacing`) / count.
  double particle_volume = 0;
  std::uint64_t seed = 1;
  // Reports long set-up work (Poisson-disk sampling) and may throw to cancel it.
  std::function<void(double done, double total)> progress;
  // Called between chunks of every loop over the particles (a few ms each);
  // throws to cancel.
  std::function<void()> check_cancelled = [] {};
};

// Fills {x in [lo, hi] : inside(x)} (lo/hi bound the shape). Throws loom::Error
// when the shape holds no particle or options are invalid.
template <int D>
Particles<D> fill_shape(const std::function<bool(const Eigen::Matrix<double, D, 1>&)>& inside,
                        const Eigen::Matrix<double, D, 1>& lo,
                        const Eigen::Matrix<double, D, 1>& hi, const EmitOptions& options);

// Generalized winding number of a closed triangle mesh at q (Jacobson et al.
// 2013): 1 inside, 0 outside, robust to small holes. V #V×3, F #F×3.
double winding_number(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                      const Eigen::Vector3d& q);

}  // namespace loom::mpm
