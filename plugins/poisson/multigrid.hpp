// Multigrid-preconditioned conjugate gradients (MGPCG, after McAdams, Sifakis
// and Teran 2010) for eq. 7 of poisson_system.hpp on a masked grid, all
// channels at once (one SIMD lane each, up to 4).
//
// The solve starts from a guess (the moved source g) and solves for the
// correction, which in normal mode is harmonic inside Ω (the smooth membrane):
// smooth errors are what multigrid removes fastest. The preconditioner is one
// symmetric V-cycle: red-black Gauss–Seidel, bilinear cell-centred
// prolongation P and restriction Pᵀ, the 5-point matrix rediscretized on
// coarse grids where a cell is unknown only if all its children are (so each
// coarse level keeps a Dirichlet boundary), and CHOLMOD on the coarsest grid.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include <opencv2/core.hpp>

#include "loom/numerics/sparse_solver.hpp"

namespace loom::poisson {

class MultigridPoisson {
 public:
  // unknown  grid mask of Ω (255 = unknown), as BlendRegion::unknown
  explicit MultigridPoisson(const cv::Mat1b& unknown);

  struct Result {
    int iterations = 0;
    double last_change = 0;  // largest |change| of a pixel in the last iteration
  };
  // Where the iterations start: at the guess g passed in f, or at g plus the
  // correction f − g of the previous solve with this hierarchy (the drag: after
  // a small move of the region the correction changes little). Either start
  // converges to the same solution; the stopping test bounds the difference.
  enum class Start { guess, previous_correction };
  // b  grid-sized CV_32FC(C), C ≤ 4, right-hand side (poisson_rhs)
  // f  grid-sized CV_32FC(C): on Ω, the guess g in, the solution out
  // Stops when an iteration changes no pixel by more than `tolerance` (in pixel
  // value units) or after max_iterations; calls between_iterations() after each.
  Result solve(const cv::Mat& b, cv::Mat& f, double tolerance, int max_iterations,
               Start start = Start::guess,
               const std::function<void()>& between_iterations = {}) const;
  int levels() const { return static_cast<int>(levels_.size()); }

  // One grid of the hierarchy; fields on it have a ring of zeros (two cells
  // on the right and bottom) so stencils need no bounds checks.
  struct Level {
    int w = 0, h = 0, stride = 0, unknowns = 0;
    std::vector<std::uint8_t> degree;  // |N_p| on Ω, 0 elsewhere
    std::size_t at(int x, int y) const { return std::size_t(y + 1) * stride + x + 1; }
    std::size_t size() const { return std::size_t(h + 4) * stride; }
  };
  struct Workspace;  // the vectors of one solve, kept for the next (the drag)

 private:
  std::vector<Level> levels_;
  std::vector<std::size_t> coarsest_cells_;  // unknowns of the last level, in matrix order
  numerics::SparseCholesky coarsest_;
  std::shared_ptr<Workspace> take_workspace() const;
  mutable std::mutex workspace_mutex_;
  mutable std::shared_ptr<Workspace> workspace_;
};

}  // namespace loom::poisson
