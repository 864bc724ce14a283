#include "exact_poisson.hpp"

#include <vector>

namespace loom::poisson {

numerics::SparseMatrix poisson_matrix(const cv::Mat1b& unknown, cv::Mat1i& index) {
  index.create(unknown.size());
  int n = 0;
  for (int y = 0; y < unknown.rows; ++y)
    for (int x = 0; x < unknown.cols; ++x) index(y, x) = unknown(y, x) ? n++ : -1;
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<size_t>(n) * 5);
  for (int y = 0; y < unknown.rows; ++y)
    for (int x = 0; x < unknown.cols; ++x) {
      const int i = index(y, x);
      if (i < 0) continue;
      // |N_p| counts neighbours inside the grid, which is inside the target.
      const int degree = (x > 0) + (x + 1 < unknown.cols) + (y > 0) + (y + 1 < unknown.rows);
      t.emplace_back(i, i, degree);
      if (x > 0 && index(y, x - 1) >= 0) t.emplace_back(i, index(y, x - 1), -1.0);
      if (x + 1 < unknown.cols && index(y, x + 1) >= 0) t.emplace_back(i, index(y, x + 1), -1.0);
      if (y > 0 && index(y - 1, x) >= 0) t.emplace_back(i, index(y - 1, x), -1.0);
      if (y + 1 < unknown.rows && index(y + 1, x) >= 0) t.emplace_back(i, index(y + 1, x), -1.0);
    }
  numerics::SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

ExactPoisson::ExactPoisson(const cv::Mat1b& unknown) {
  cv::Mat1i index;
  const numerics::SparseMatrix A = poisson_matrix(unknown, index);
  pixels_.reserve(A.rows());
  for (int y = 0; y < unknown.rows; ++y)
    for (int x = 0; x < unknown.cols; ++x)
      if (unknown(y, x)) pixels_.emplace_back(x, y);
  cholesky_.compute(A);
}

void ExactPoisson::solve(const cv::Mat& b, cv::Mat& f) const {
  const int C = b.channels(), n = unknowns();
  Eigen::MatrixXd B(n, C);
  for (int i = 0; i < n; ++i) {
    const float* v = b.ptr<float>(pixels_[i].y) + pixels_[i].x * C;
    for (int c = 0; c < C; ++c) B(i, c) = v[c];
  }
  const Eigen::MatrixXd X = cholesky_.solve(B);
  for (int i = 0; i < n; ++i) {
    float* v = f.ptr<float>(pixels_[i].y) + pixels_[i].x * C;
    for (int c = 0; c < C; ++c) v[c] = static_cast<float>(X(i, c));
  }
}

}  // namespace loom::poisson
