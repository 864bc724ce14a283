// MLS-MPM (Hu et al. 2018) with quadratic B-splines and APIC affine velocities,
// one code path for D = 2 and 3. The domain is the cube [0, size]^D on a grid of
// `resolution` cells per axis (Δx = size / resolution), nodes at i Δx.
//
// Parallel P2G: coloured blocks. Particles are binned (a counting sort, stable in
// particle index) into blocks of B cells per axis by the lowest node of their
// stencil; a particle's 3^D stencil then stays inside its block and the next one,
// so blocks whose coordinates have the same parities (2^D colours) never write the
// same node. Colours run one after another, the blocks of a colour in parallel,
// each block's particles in index order: every node sums its contributions in the
// same order whatever the thread count, so results are bit-identical. Per-thread
// grids would cost a grid-sized reduction per thread per substep (128³ = 2M nodes,
// more than the particles of a typical 3D scene) and an order that depends on the
// thread count.
#pragma once

#include <array>
#include <atomic>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "constitutive.hpp"
#include "particles.hpp"

namespace loom::mpm {

enum class Boundary { sticky, slip, separate };

struct Collider {
  enum class Shape { plane, sphere } shape = Shape::plane;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   // plane: a point; sphere: the centre
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY();  // plane: towards the free side
  double radius = 0;                                   // sphere
  Boundary boundary = Boundary::slip;
};

struct Settings {
  int resolution = 128;
  double size = 1;
  Eigen::Vector3d gravity = Eigen::Vector3d(0, -9.8, 0);  // first D components used
  Boundary walls = Boundary::separate;
  int wall_cells = 3;                 // grid nodes this close to a wall take its condition
  bool walls_enabled = true;          // false: an open domain (particles are still kept in it)
  std::vector<Collider> colliders;
  double cfl = 0.4;                   // Δt ≤ cfl Δx / (max |v| + sound speed)
  double dt_max = 1e-3;               // the user's cap on Δt
  int max_substeps = 100000;          // per advance(): beyond it, an error instead of a hang
  SandModel sand;                     // friction angle, hardening (Klár 2016 §7.3)
};

struct AdvanceReport {
  int substeps = 0;
  double dt_min = 0, dt_max = 0;
  long clamped_deformation = 0;  // particles whose J or singular values were clamped
  long clamped_positions = 0;    // particles put back inside the domain
};

template <int D>
class Solver {
 public:
  using Vec = Eigen::Matrix<double, D, 1>;
  using Mat = Eigen::Matrix<double, D, D>;
  using Node = Eigen::Matrix<double, D + 1, 1>;  // momentum (then velocity), mass

  // A block's size in cells along each axis (see the top of this file).
  static constexpr int kBlockCells = D == 2 ? 8 : 4;

  explicit Solver(const Settings& settings);

  // Advances by `seconds` in substeps of Δt = remaining / ⌈remaining / Δt_CFL⌉
  // (so the last one lands on the frame). `between` runs on the calling thread
  // after each substep with the fraction done (for progress and cancellation).
  AdvanceReport advance(Particles<D>& ps, double seconds,
                        const std::function<void(double)>& between = {});

  // One substep: P2G, grid update, G2P. Returns max over particles of
  // (|v| + sound speed) afterwards, for the next CFL step.
  double substep(Particles<D>& ps, double dt);

  // A copy of the particles in the order advance() runs its substeps in: by block
  // (see bin), then by index. For timing substeps as a frame runs them.
  Particles<D> in_block_order(const Particles<D>& ps);

  // Keeps particles inside [2Δx, size − 2Δx]^D; returns how many were moved.
  long clamp_positions(Particles<D>& ps) const;
  // max over particles of |v| + sound speed √((λ + 2μ) h / ρ).
  double max_signal_speed(const Particles<D>& ps) const;
  double dx() const { return dx_; }
  double cfl_dt(double signal_speed) const;

  const std::vector<Node>& grid() const { return grid_; }  // after the last substep
  // The nodes the last substep's grid update visited: those of the blocks its
  // particles could reach (every other node is zero).
  long reachable_nodes() const;
  long clamped_deformation() const { return clamped_.load(); }

 private:
  void bin(const Particles<D>& ps);
  // Each particle's place in block order (in_block_order).
  std::vector<int> block_order_slots(const Particles<D>& ps);
  // Block b's position along each axis, in blocks.
  std::array<int, D> block_coordinates(int b) const;
  void mark_reachable_blocks();
  template <typename F>
  void for_nodes_of_blocks(const std::vector<int>& blocks, const F& f);
  void p2g(Particles<D>& ps, double dt);
  void grid_update(double dt);
  double g2p(Particles<D>& ps, double dt);

  Settings s_;
  int n_;
  double dx_, inv_dx_;
  Eigen::Matrix<long, D, 1> stride_;
  std::vector<Node> grid_;
  // P2G's scatter reads each particle's position, velocity, mass and affine
  // momentum (from the stress pass), block by block. In 3D the stress pass copies
  // them into scatter_inputs_ in that order, and the scatter reads them one after
  // another; in 2D the scatter reads them where they are, affine_ by particle
  // index, in order_ (measured in docs/mpm.md: in 3D the copy saves more than it
  // costs, in 2D it does not), and computes a fluid particle's affine momentum
  // itself (the stress pass skips the fluid there).
  static constexpr bool kBlockOrderedInputs = D == 3;
  struct alignas(64) ScatterInput {  // 3D: 128 bytes, two cache lines
    ScatterInput() {}                // left unset, as Eigen leaves its matrices: resize() writes nothing
    Vec x;
    double mass;
    Vec v;
    Mat affine;
  };
  std::vector<ScatterInput> scatter_inputs_;  // by place in block order
  std::vector<Mat> affine_;                   // by particle
  // Binning workspace, kept across substeps (no allocation per substep).
  int blocks_per_axis_;
  std::vector<int> block_of_, block_start_;
  std::vector<int> order_;   // 2D: the particles in block order (by block, then index)
  std::vector<int> slot_;    // 3D: each particle's place in that order
  std::vector<int> cursor_;  // per chunk of particles and block: a count, then a write cursor
  std::vector<int> colour_blocks_[1 << D];
  // The blocks whose nodes particles can reach (a block with particles and the
  // next one along each axis), this substep and the last: only their nodes are
  // cleared and updated; every other node has stayed zero.
  std::vector<char> reachable_, reachable_before_;
  std::vector<int> to_clear_, to_update_;
  std::atomic<long> clamped_{0};
  std::atomic<bool> diverged_{false};  // a particle's new velocity was NaN or infinite
};

}  // namespace loom::mpm
