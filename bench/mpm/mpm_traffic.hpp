// The memory traffic of one MLS-MPM substep (plugins/mpm/mls_mpm.cpp), and a
// loop that moves the same bytes and computes nothing: the bandwidth limit of
// the particle code, in bytes per particle-substep and as a rate.
//
// Bytes are counted as STREAM counts them: each byte read or written once per
// pass, no write-allocate, from what the solver's code touches:
//   bin  x read; block_of written (and counted), then read to scatter; order written
//   P2G  the stress pass reads C, mass, volume, material and J, λ (fluid) or
//        F, μ, λ (solids), and writes each particle's affine matrix; the
//        scatter reads order, x, v, mass and the affine matrix
//   G2P  x read and written; v, C written; fluid: J read and written; solids:
//        F read and written; the sound speed reads material, μ, λ, mass,
//        volume (and J for solids)
//   grid the clear writes every node of the blocks particles can reach, this
//        substep's and the last's (the same blocks when particles barely
//        move, as in the bench); the update reads those of this substep and
//        writes the nodes with mass. P2G's and G2P's node accesses are counted as
//        cache hits: a block's particles (about 1,500 in the 2D scenes, 500 in
//        3D) share its stencil of 10² or 6³ nodes (2.4 or 6.9 KB), and the
//        nodes with mass (1 MB in 2D, 5 MB in 3D) fit in the 32 MB L3.
#pragma once

#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "particles.hpp"

namespace loom::mpm::traffic {

// Particle-state bytes of one substep per particle.
template <int D>
double particle_bytes(Material m) {
  using P = Particles<D>;
  const double vec = sizeof(typename P::Vec), mat = sizeof(typename P::Mat), real = sizeof(double);
  const double index = sizeof(int), material = sizeof(Material);
  const bool fluid = m == Material::fluid;
  const double bin = vec + 3 * index;
  const double p2g = index + 2 * vec + 3 * mat + 3 * real + material + (fluid ? 2 * real : mat + 2 * real);
  const double g2p = 3 * vec + mat + material + 4 * real + (fluid ? 2 * real : 2 * mat + real);
  return bin + p2g + g2p;
}

// Grid bytes of one substep: `nodes` cleared and updated, `with_mass` of them reached by particles.
template <int D>
double grid_bytes(long nodes, long with_mass) {
  const double node = sizeof(Eigen::Matrix<double, D + 1, 1>);
  return (2.0 * static_cast<double>(nodes) + static_cast<double>(with_mass)) * node;
}

// Moves particle_bytes<D>(m) per particle and grid_bytes<D>(nodes, with_mass)
// per call, touching the same arrays in the same passes as a substep (in index
// order; the solver's P2G visits them block by block, nearly the same order for
// the emitters' Morton-sorted particles), with no arithmetic beyond what keeps
// the loads alive. Particles of one material.
template <int D>
class StreamingProxy {
 public:
  using Node = Eigen::Matrix<double, D + 1, 1>;
  StreamingProxy(long nodes, long with_mass) : grid_(static_cast<std::size_t>(nodes)), with_mass_(with_mass) {}

  void run(Particles<D>& ps) {
    const int n = ps.size();
    block_.resize(static_cast<std::size_t>(n));
    order_.resize(static_cast<std::size_t>(n));
    const bool fluid = ps.material[0] == Material::fluid;
    for_particles(n, [&](int p) { block_[p] = static_cast<int>(ps.x[p][0] * 512); });
    for_particles(n, [&](int p) { order_[p] = block_[p] + 1; });
    for_nodes([&](std::size_t i) { grid_[i].setZero(); });
    affine_.resize(static_cast<std::size_t>(n));
    for_particles(n, [&](int p) {  // P2G's stress pass
      const double s = ps.mass[p] + ps.volume[p] + static_cast<double>(ps.material[p]) + ps.lambda[p] +
                       (fluid ? ps.J[p] : ps.F[p].sum() + ps.mu[p]);
      affine_[static_cast<std::size_t>(p)] = ps.C[p] * s;
    });
    sink_ += sum_particles(n, [&](int p) {  // P2G's scatter reads
      return order_[p] + ps.x[p].sum() + ps.v[p].sum() + ps.mass[p] + affine_[static_cast<std::size_t>(p)].sum();
    });
    sink_ += sum_nodes([&](std::size_t i) { return grid_[i].sum(); });
    for_nodes([&](std::size_t i) {
      if (static_cast<long>(i) < with_mass_) grid_[i][0] = 1;
    });
    const double one = 1 + sink_ * 0;  // a run-time 1: the stores below cannot be dropped
    for_particles(n, [&](int p) {      // G2P's reads and writes
      const double s = ps.mass[p] + ps.volume[p] + ps.mu[p] + ps.lambda[p] + static_cast<double>(ps.material[p]);
      ps.x[p] *= one;
      ps.v[p].setConstant(s);
      ps.C[p].setConstant(s);
      if (fluid)
        ps.J[p] *= one;
      else
        ps.F[p] *= one, ps.C[p](0, 0) += ps.J[p];
    });
  }
  double checksum() const { return sink_; }

 private:
  template <class F>
  static void for_particles(int n, const F& f) {
    tbb::parallel_for(tbb::blocked_range<int>(0, n, 4096), [&](const tbb::blocked_range<int>& r) {
      for (int p = r.begin(); p < r.end(); ++p) f(p);
    });
  }
  template <class F>
  static double sum_particles(int n, const F& f) {
    return tbb::parallel_reduce(
        tbb::blocked_range<int>(0, n, 4096), 0.0,
        [&](const tbb::blocked_range<int>& r, double s) {
          for (int p = r.begin(); p < r.end(); ++p) s += f(p);
          return s;
        },
        [](double a, double b) { return a + b; });
  }
  template <class F>
  void for_nodes(const F& f) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, grid_.size(), 1 << 14),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i < r.end(); ++i) f(i);
                      });
  }
  template <class F>
  double sum_nodes(const F& f) {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, grid_.size(), 1 << 14), 0.0,
        [&](const tbb::blocked_range<std::size_t>& r, double s) {
          for (std::size_t i = r.begin(); i < r.end(); ++i) s += f(i);
          return s;
        },
        [](double a, double b) { return a + b; });
  }

  std::vector<Node> grid_;
  long with_mass_;
  std::vector<int> block_, order_;
  std::vector<typename Particles<D>::Mat> affine_;
  double sink_ = 0;
};

}  // namespace loom::mpm::traffic
