// Newton's assembled matrix is the Jacobian of the gradient it solves with:
// M + h² Σ H_s + h² ∇²P against central differences of ∇E + h² ∇P, on a
// system whose springs are all stretched (where the clamp of H_s is
// inactive, H_s is the springs' exact Hessian), with fixed vertices, a
// spring between two fixed ones, a repeated spring and a free vertex on no
// spring that only the penalty touches; assembled twice with one workspace,
// so the second, refilled in place, must hold nothing of the first.
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "implicit_solvers.hpp"
#include "incremental_potential.hpp"

namespace loom::cloth {
namespace {

// 8 vertices: 0-3 a free tetrahedron of springs (0-1 twice), 4 and 5 fixed
// (springs 0-4 and 4-5), 6 free on one spring to 5, 7 free on none.
SpringSystem test_system(std::mt19937& rng) {
  std::uniform_real_distribution<double> coord(-1, 1), mass(0.5, 2), k(10, 100);
  SpringSystem s;
  s.X.resize(8, 3);
  for (int i = 0; i < 8; ++i) s.X.row(i) << coord(rng), coord(rng), coord(rng);
  s.springs.resize(9, 2);
  s.springs << 0, 1, 0, 2, 0, 3, 1, 2, 1, 3, 2, 3, 0, 1, 0, 4, 4, 5;
  s.springs.conservativeResize(10, 2);
  s.springs.row(9) << 5, 6;
  s.mass.resize(8);
  for (int i = 0; i < 8; ++i) s.mass[i] = mass(rng);
  s.fixed = Eigen::VectorXi::Zero(8);
  s.fixed[4] = s.fixed[5] = 1;
  s.stiffness.resize(10);
  s.rest_length.resize(10);
  for (int k_s = 0; k_s < 10; ++k_s) s.stiffness[k_s] = k(rng);
  return s;
}

// P(x) = ½ Σ_v (x_v − c)ᵀ B_v (x_v − c) on vertices 2, 6 and 7 (B_v symmetric
// positive definite): ∇P = B_v (x_v − c), its Hessian blocks B_v.
struct Penalty {
  std::vector<int> vertex{2, 6, 7};
  std::vector<Eigen::Matrix3d> B;
  Eigen::Vector3d c{0.1, -0.2, 0.3};
  explicit Penalty(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1, 1);
    for (size_t i = 0; i < vertex.size(); ++i) {
      const Eigen::Matrix3d A = Eigen::Matrix3d::NullaryExpr([&] { return u(rng); });
      const Eigen::Matrix3d AAt = A * A.transpose();
      B.push_back(0.5 * (AAt + AAt.transpose()) + Eigen::Matrix3d::Identity());  // symmetric to the bit
    }
  }
  double operator()(const Eigen::MatrixX3d& x, Eigen::MatrixX3d* gradient,
                    std::vector<std::pair<int, Eigen::Matrix3d>>* blocks) const {
    double p = 0;
    for (size_t i = 0; i < vertex.size(); ++i) {
      const Eigen::Vector3d d = x.row(vertex[i]).transpose() - c;
      p += 0.5 * d.dot(B[i] * d);
      if (gradient) gradient->row(vertex[i]) += (B[i] * d).transpose();
      if (blocks) blocks->emplace_back(vertex[i], B[i]);
    }
    return p;
  }
};

// ∇(E + h² P) over the free unknowns, in the workspace's row order.
Eigen::VectorXd free_gradient(const SpringSystem& s, const Penalty& penalty, const std::vector<int>& row, int unknowns,
                              const Eigen::MatrixX3d& x, const Eigen::MatrixX3d& y, double h) {
  Eigen::MatrixX3d g = incremental_gradient(s, x, y, h);
  Eigen::MatrixX3d gp = Eigen::MatrixX3d::Zero(x.rows(), 3);
  penalty(x, &gp, nullptr);
  Eigen::VectorXd out(unknowns);
  for (int i = 0; i < s.vertices(); ++i)
    if (row[i] >= 0) out.segment<3>(row[i]) = (g.row(i) + h * h * gp.row(i)).transpose();
  return out;
}

TEST(NewtonHessian, IsTheJacobianOfTheGradientAndKeepsNothingOfTheLastAssembly) {
  std::mt19937 rng(11);
  SpringSystem s = test_system(rng);
  const Penalty penalty(rng);
  const double h = 0.05;
  std::uniform_real_distribution<double> jitter(-0.1, 0.1);
  NewtonWorkspace workspace;
  workspace.prepare(s);
  const std::vector<int> row = workspace.rows();
  const int unknowns = workspace.unknowns();
  ASSERT_EQ(unknowns, 18);
  SolveOptions options;
  options.penalty = [&](const Eigen::MatrixX3d& x, Eigen::MatrixX3d* g,
                        std::vector<std::pair<int, Eigen::Matrix3d>>* b) { return penalty(x, g, b); };
  for (int assembly = 0; assembly < 2; ++assembly) {
    Eigen::MatrixX3d x = s.X;
    for (int i = 0; i < x.rows(); ++i)
      if (!s.fixed[i]) x.row(i) += Eigen::RowVector3d(jitter(rng), jitter(rng), jitter(rng));
    // Every spring stretched at x: rest lengths 0.6–0.9 of its length there.
    for (int k = 0; k < s.spring_count(); ++k)
      s.rest_length[k] = (0.6 + 0.1 * (k % 4)) * (x.row(s.springs(k, 0)) - x.row(s.springs(k, 1))).norm();
    const Eigen::MatrixX3d y = x + Eigen::MatrixX3d::Constant(x.rows(), 3, 0.01);
    const Eigen::MatrixXd H = Eigen::MatrixXd(workspace.hessian(s, x, h, options));
    Eigen::MatrixXd J(unknowns, unknowns);
    const double step = 1e-6;
    for (int i = 0; i < s.vertices(); ++i)
      for (int c = 0; c < 3 && row[i] >= 0; ++c) {
        Eigen::MatrixX3d plus = x, minus = x;
        plus(i, c) += step;
        minus(i, c) -= step;
        J.col(row[i] + c) = (free_gradient(s, penalty, row, unknowns, plus, y, h) -
                             free_gradient(s, penalty, row, unknowns, minus, y, h)) /
                            (2 * step);
      }
    EXPECT_LT((H - J).norm(), 1e-7 * J.norm()) << "assembly " << assembly;
    EXPECT_EQ((H - H.transpose()).norm(), 0.0);
    // Stored: the diagonal blocks of the 6 free vertices and the two blocks
    // of each of the 6 distinct free-free pairs, 9 entries each.
    EXPECT_EQ(workspace.hessian(s, x, h, options).nonZeros(), 9 * (6 + 2 * 6));
  }
}

}  // namespace
}  // namespace loom::cloth
