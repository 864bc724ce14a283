// The exact solve of eq. 7 (poisson_system.hpp): the matrix assembled over Ω
// and factored once by CHOLMOD (supernodal); each solve is a back-substitution
// for all channels at once. The reference the fast solvers are measured against,
// and the cheapest re-solve when only the offset changes (the drag).
#pragma once

#include <opencv2/core.hpp>

#include "loom/numerics/sparse_solver.hpp"

namespace loom::poisson {

class ExactPoisson {
 public:
  // unknown  grid mask of Ω (255 = unknown), as BlendRegion::unknown
  explicit ExactPoisson(const cv::Mat1b& unknown);
  // b  grid-sized CV_32FC(C) right-hand side (poisson_rhs)
  // f  grid-sized CV_32FC(C); its Ω pixels are overwritten with the solution
  void solve(const cv::Mat& b, cv::Mat& f) const;
  int unknowns() const { return static_cast<int>(pixels_.size()); }

 private:
  std::vector<cv::Point> pixels_;  // Ω in grid coordinates, in unknown order
  numerics::SparseCholesky cholesky_;
};

// The matrix of eq. 7 over Ω: |N_p| on the diagonal, −1 for each pair of
// neighbouring unknowns; unknowns numbered row by row. index: grid-sized,
// unknown number or −1. Returns n by n (both triangles).
numerics::SparseMatrix poisson_matrix(const cv::Mat1b& unknown, cv::Mat1i& index);

}  // namespace loom::poisson
