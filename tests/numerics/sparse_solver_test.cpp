// CHOLMOD and UMFPACK behind the facade, against Eigen's own solvers, dense
// solves and a Laplace problem whose discrete solution is known exactly.
#include <dlfcn.h>

#include <cmath>
#include <cstdlib>
#include <random>
#include <thread>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <gtest/gtest.h>

#include "loom/error.hpp"
#include "loom/numerics/sparse_solver.hpp"

namespace loom::numerics {
namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

// A random sparse SPD matrix: R^T R + I with R sparse (about `per_col` per column).
SparseMatrix random_spd(int n, int per_col, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> row(0, n - 1);
  std::uniform_real_distribution<double> val(-1, 1);
  Triplets t;
  for (int j = 0; j < n; ++j)
    for (int k = 0; k < per_col; ++k) t.emplace_back(row(rng), j, val(rng));
  SparseMatrix R(n, n);
  R.setFromTriplets(t.begin(), t.end());
  SparseMatrix I(n, n);
  I.setIdentity();
  SparseMatrix A = SparseMatrix(R.transpose()) * R + I;
  A.makeCompressed();
  return A;
}

// A random sparse non-symmetric matrix, diagonally dominant so it is invertible.
SparseMatrix random_general(int n, int per_col, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> row(0, n - 1);
  std::uniform_real_distribution<double> val(-1, 1);
  Triplets t;
  for (int j = 0; j < n; ++j) {
    for (int k = 0; k < per_col; ++k) t.emplace_back(row(rng), j, val(rng));
    t.emplace_back(j, j, per_col + 1.0 + val(rng));
  }
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

Eigen::MatrixXd random_rhs(int n, int k, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> val(-1, 1);
  Eigen::MatrixXd B(n, k);
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < n; ++i) B(i, j) = val(rng);
  return B;
}

double rel_error(const Eigen::MatrixXd& X, const Eigen::MatrixXd& ref) {
  return (X - ref).norm() / ref.norm();
}

// 5-point Laplacian (the negative, so SPD) on the interior of an (m+2)^2 grid
// with spacing h; unknown (i, j) at index j*m + i.
SparseMatrix laplacian_2d(int m, double h) {
  Triplets t;
  auto id = [m](int i, int j) { return j * m + i; };
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      t.emplace_back(id(i, j), id(i, j), 4 / (h * h));
      if (i > 0) t.emplace_back(id(i, j), id(i - 1, j), -1 / (h * h));
      if (i + 1 < m) t.emplace_back(id(i, j), id(i + 1, j), -1 / (h * h));
      if (j > 0) t.emplace_back(id(i, j), id(i, j - 1), -1 / (h * h));
      if (j + 1 < m) t.emplace_back(id(i, j), id(i, j + 1), -1 / (h * h));
    }
  SparseMatrix A(m * m, m * m);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

TEST(SparseCholesky, MatchesSimplicialLDLTOnRandomSpd) {
  const SparseMatrix A = random_spd(400, 3, 1);
  const Eigen::MatrixXd B = random_rhs(400, 5, 2);
  SparseCholesky chol;
  chol.compute(A);
  EXPECT_STREQ(chol.backend(), "cholmod");
  EXPECT_EQ(chol.rows(), 400);
  Eigen::SimplicialLDLT<SparseMatrix> ldlt(A);
  ASSERT_EQ(ldlt.info(), Eigen::Success);
  const Eigen::MatrixXd ref = ldlt.solve(B);
  EXPECT_LT(rel_error(chol.solve(B), ref), 1e-10);
}

TEST(SparseCholesky, MatchesDenseSolve) {
  const SparseMatrix A = random_spd(60, 4, 3);
  const Eigen::MatrixXd B = random_rhs(60, 3, 4);
  SparseCholesky chol;
  chol.compute(A);
  const Eigen::MatrixXd ref = Eigen::MatrixXd(A).llt().solve(B);
  EXPECT_LT(rel_error(chol.solve(B), ref), 1e-11);
}

TEST(SparseCholesky, LowerTriangleOnlyAndUncompressedGiveTheSameSolution) {
  const SparseMatrix A = random_spd(200, 3, 5);
  const Eigen::MatrixXd B = random_rhs(200, 2, 6);
  SparseCholesky full, lower, loose;
  full.compute(A);
  lower.compute(SparseMatrix(A.triangularView<Eigen::Lower>()));
  SparseMatrix U = A;
  U.uncompress();  // Eigen's unpacked storage, read by CHOLMOD without a copy
  U.coeffRef(0, 0) += 0.0;
  ASSERT_FALSE(U.isCompressed());
  loose.compute(U);
  const Eigen::MatrixXd X = full.solve(B);
  EXPECT_LT(rel_error(lower.solve(B), X), 1e-12);
  EXPECT_LT(rel_error(loose.solve(B), X), 1e-12);
}

// u = x(1-x) y(1-y) on [0,1]^2, u = 0 on the boundary. The second difference
// of a quadratic is exact, so the discrete solution of -Δ_h u = f with
// f = 2 y(1-y) + 2 x(1-x) equals u at the nodes up to round-off.
TEST(SparseCholesky, TwoDimensionalLaplacianHasTheAnalyticSolution) {
  const int m = 127;
  const double h = 1.0 / (m + 1);
  const SparseMatrix A = laplacian_2d(m, h);
  Eigen::VectorXd f(m * m), u(m * m);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      const double x = (i + 1) * h, y = (j + 1) * h;
      f[j * m + i] = 2 * y * (1 - y) + 2 * x * (1 - x);
      u[j * m + i] = x * (1 - x) * y * (1 - y);
    }
  SparseCholesky chol;
  chol.compute(A);
  const Eigen::VectorXd x = chol.solve(f);
  EXPECT_LT((x - u).cwiseAbs().maxCoeff(), 1e-12);
}

// u = sin(πx) sin(πy): the 5-point scheme converges at O(h²).
TEST(SparseCholesky, TwoDimensionalLaplacianConvergesSecondOrder) {
  double err[2];
  const int sizes[2] = {31, 63};
  for (int s = 0; s < 2; ++s) {
    const int m = sizes[s];
    const double h = 1.0 / (m + 1), pi = 3.14159265358979323846;
    Eigen::VectorXd f(m * m), u(m * m);
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) {
        u[j * m + i] = std::sin(pi * (i + 1) * h) * std::sin(pi * (j + 1) * h);
        f[j * m + i] = 2 * pi * pi * u[j * m + i];
      }
    SparseCholesky chol;
    chol.compute(laplacian_2d(m, h));
    err[s] = (chol.solve(f) - u).cwiseAbs().maxCoeff();
  }
  EXPECT_NEAR(err[0] / err[1], 4.0, 0.2);  // halving h quarters the error
}

TEST(SparseCholesky, RefactorWithNewValuesMatchesAFreshFactorization) {
  const SparseMatrix A = random_spd(300, 3, 7);
  const Eigen::MatrixXd B = random_rhs(300, 3, 8);
  SparseCholesky chol;
  chol.compute(A);
  SparseMatrix A2 = A * 2.5;
  for (int i = 0; i < A2.rows(); ++i) A2.coeffRef(i, i) += 0.1 * i;
  chol.refactor(A2);
  Eigen::SimplicialLDLT<SparseMatrix> ldlt(A2);
  EXPECT_LT(rel_error(chol.solve(B), ldlt.solve(B)), 1e-10);
}

// The factor kept in simplicial form for many solves: the same solutions as
// the supernodal one, after compute() and after refactor() with new values.
TEST(SparseCholesky, SimplicialSolvesMatchTheSupernodalFactor) {
  const SparseMatrix A = laplacian_2d(60, 1.0 / 61);
  const Eigen::MatrixXd B = random_rhs(3600, 3, 12);
  SparseCholesky supernodal, simplicial(SparseCholesky::Options{true});
  supernodal.compute(A);
  simplicial.compute(A);
  Eigen::SimplicialLDLT<SparseMatrix> ldlt(A);
  EXPECT_LT(rel_error(simplicial.solve(B), ldlt.solve(B)), 1e-12);
  EXPECT_LT(rel_error(simplicial.solve(B), supernodal.solve(B)), 1e-12);
  SparseMatrix A2 = A * 2.5;
  for (int i = 0; i < A2.rows(); ++i) A2.coeffRef(i, i) += 0.1 * i;
  simplicial.refactor(A2);
  EXPECT_LT(rel_error(simplicial.solve(B), Eigen::SimplicialLDLT<SparseMatrix>(A2).solve(B)), 1e-12);
}

TEST(SparseCholesky, RefactorWithAnotherPatternFallsBackToCompute) {
  SparseCholesky chol;
  chol.refactor(random_spd(100, 2, 9));  // no compute() yet
  const SparseMatrix A = random_spd(150, 3, 10);
  chol.refactor(A);
  const Eigen::MatrixXd B = random_rhs(150, 1, 11);
  EXPECT_EQ(chol.rows(), 150);
  EXPECT_LT(rel_error(chol.solve(B), Eigen::MatrixXd(A).llt().solve(B)), 1e-10);
}

TEST(SparseCholesky, NotPositiveDefiniteIsAClearError) {
  SparseMatrix A = laplacian_2d(10, 1.0);
  A.coeffRef(37, 37) = -5.0;  // an indefinite pivot
  SparseCholesky chol;
  try {
    chol.compute(A);
    FAIL() << "expected loom::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not positive definite"), std::string::npos) << e.what();
  }
  EXPECT_THROW(chol.solve(Eigen::VectorXd::Ones(100)), Error);  // no stale factor is used
  // The same object recovers once given a valid matrix.
  chol.refactor(laplacian_2d(10, 1.0));
  EXPECT_NO_THROW(chol.solve(Eigen::VectorXd::Ones(100)));
}

TEST(SparseCholesky, SingularLaplacianWithoutDirichletIsNotPositiveDefinite) {
  // The graph Laplacian of a path: positive semi-definite with the constants in its kernel.
  const int n = 50;
  Triplets t;
  for (int i = 0; i + 1 < n; ++i) {
    t.emplace_back(i, i, 1);
    t.emplace_back(i + 1, i + 1, 1);
    t.emplace_back(i, i + 1, -1);
    t.emplace_back(i + 1, i, -1);
  }
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  SparseCholesky chol;
  EXPECT_THROW(chol.compute(A), Error);
}

TEST(SparseCholesky, BadInputIsAClearError) {
  SparseCholesky chol;
  EXPECT_THROW(chol.solve(Eigen::VectorXd::Ones(3)), Error);  // before compute
  EXPECT_THROW(chol.compute(SparseMatrix(3, 4)), Error);
  EXPECT_THROW(chol.compute(SparseMatrix(0, 0)), Error);
  SparseMatrix A = laplacian_2d(4, 1.0);
  A.coeffRef(2, 2) = std::nan("");
  EXPECT_THROW(chol.compute(A), Error);
  chol.compute(laplacian_2d(4, 1.0));
  EXPECT_THROW(chol.solve(Eigen::VectorXd::Ones(15)), Error);
}

TEST(SparseCholesky, ConcurrentSolvesAgree) {
  const SparseMatrix A = random_spd(500, 3, 12);
  SparseCholesky chol;
  chol.compute(A);
  const Eigen::MatrixXd B = random_rhs(500, 16, 13);
  const Eigen::MatrixXd X = chol.solve(B);
  std::vector<double> err(16);
  std::vector<std::thread> threads;
  for (int j = 0; j < 16; ++j)
    threads.emplace_back([&, j] { err[j] = (chol.solve(B.col(j)) - X.col(j)).cwiseAbs().maxCoeff(); });
  for (std::thread& t : threads) t.join();
  for (double e : err) EXPECT_LT(e, 1e-12);
}

// OpenBLAS's own thread pool spins outside the engine's TBB limit: the
// facade runs BLAS on the calling thread unless the user asked otherwise.
TEST(SparseCholesky, BlasRunsOnTheCallingThread) {
  if (std::getenv("OPENBLAS_NUM_THREADS")) GTEST_SKIP() << "OPENBLAS_NUM_THREADS is set: the user's choice stands";
  SparseCholesky chol;
  chol.compute(random_spd(200, 3, 21));
  void* openblas = dlopen("libopenblas.so.0", RTLD_LAZY | RTLD_NOLOAD);
  if (!openblas) GTEST_SKIP() << "BLAS is not OpenBLAS";
  using GetThreads = int (*)();
  const auto get = reinterpret_cast<GetThreads>(dlsym(openblas, "openblas_get_num_threads"));
  ASSERT_NE(get, nullptr);
  EXPECT_EQ(get(), 1);
  dlclose(openblas);
}

TEST(SparseCholesky, MovedObjectKeepsItsFactor) {
  const SparseMatrix A = random_spd(80, 3, 14);
  const Eigen::MatrixXd B = random_rhs(80, 2, 15);
  SparseCholesky a;
  a.compute(A);
  SparseCholesky b = std::move(a);
  EXPECT_LT(rel_error(b.solve(B), Eigen::MatrixXd(A).llt().solve(B)), 1e-11);
}

TEST(SparseLU, MatchesEigenSparseLUOnRandomNonSymmetric) {
  const SparseMatrix A = random_general(500, 4, 16);
  const Eigen::MatrixXd B = random_rhs(500, 4, 17);
  SparseLU lu;
  lu.compute(A);
  EXPECT_STREQ(lu.backend(), "umfpack");
  Eigen::SparseLU<SparseMatrix> ref(A);
  ASSERT_EQ(ref.info(), Eigen::Success);
  EXPECT_LT(rel_error(lu.solve(B), ref.solve(B)), 1e-10);
}

TEST(SparseLU, MatchesDenseSolve) {
  const SparseMatrix A = random_general(70, 5, 18);
  const Eigen::MatrixXd B = random_rhs(70, 3, 19);
  SparseLU lu;
  lu.compute(A);
  EXPECT_LT(rel_error(lu.solve(B), Eigen::MatrixXd(A).partialPivLu().solve(B)), 1e-11);
}

TEST(SparseLU, SolvesTheLaplacianLikeCholesky) {
  const SparseMatrix A = laplacian_2d(40, 1.0 / 41);
  const Eigen::MatrixXd B = random_rhs(1600, 2, 20);
  SparseLU lu;
  lu.compute(A);
  SparseCholesky chol;
  chol.compute(A);
  EXPECT_LT(rel_error(lu.solve(B), chol.solve(B)), 1e-10);
}

// A graph Laplacian with positive, non-symmetric weights and Dirichlet rows
// folded in (as mean-value weights give): a diagonally dominant M-matrix.
SparseMatrix nonsymmetric_m_matrix(int m, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> w(0.1, 2.0);
  Triplets t;
  auto id = [m](int i, int j) { return j * m + i; };
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      double sum = 0;
      for (const auto& [di, dj] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
        const double wij = w(rng);
        sum += wij;
        const int a = i + di, b = j + dj;
        if (a >= 0 && a < m && b >= 0 && b < m) t.emplace_back(id(i, j), id(a, b), -wij);
      }
      t.emplace_back(id(i, j), id(i, j), sum);
    }
  SparseMatrix A(m * m, m * m);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

TEST(SparseLU, WithoutRefinementMatchesDenseSolveOnMMatrix) {
  const SparseMatrix A = nonsymmetric_m_matrix(30, 22);
  const Eigen::MatrixXd B = random_rhs(900, 2, 23);
  const Eigen::MatrixXd ref = Eigen::MatrixXd(A).partialPivLu().solve(B);
  SparseLU plain(SparseLU::Options{0});
  plain.compute(A);
  EXPECT_LT(rel_error(plain.solve(B), ref), 1e-12);
  SparseLU refined;
  refined.compute(A);
  EXPECT_LT(rel_error(refined.solve(B), ref), 1e-12);
}

TEST(SparseLU, WithoutRefinementMatchesEigenSparseLUOnRandomNonSymmetric) {
  const SparseMatrix A = random_general(500, 4, 24);
  const Eigen::MatrixXd B = random_rhs(500, 3, 25);
  SparseLU lu(SparseLU::Options{0});
  lu.compute(A);
  Eigen::SparseLU<SparseMatrix> ref(A);
  ASSERT_EQ(ref.info(), Eigen::Success);
  EXPECT_LT(rel_error(lu.solve(B), ref.solve(B)), 1e-10);
}

TEST(SparseLU, NegativeRefinementStepsIsAClearError) {
  try {
    SparseLU lu(SparseLU::Options{-1});
    FAIL() << "expected loom::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("refinement_steps"), std::string::npos) << e.what();
  }
}

TEST(SparseLU, SingularMatrixIsAClearError) {
  Triplets t = {{0, 0, 1}, {0, 1, 2}, {1, 0, 2}, {1, 1, 4}, {2, 2, 3}};  // rows 0 and 1 dependent
  SparseMatrix A(3, 3);
  A.setFromTriplets(t.begin(), t.end());
  SparseLU lu;
  try {
    lu.compute(A);
    FAIL() << "expected loom::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("singular"), std::string::npos) << e.what();
  }
  EXPECT_THROW(lu.solve(Eigen::VectorXd::Ones(3)), Error);
  SparseMatrix Z(3, 3);  // structurally singular: no entries at all
  EXPECT_THROW(lu.compute(Z), Error);
}

TEST(SparseLU, BadInputIsAClearError) {
  SparseLU lu;
  EXPECT_THROW(lu.solve(Eigen::VectorXd::Ones(3)), Error);
  EXPECT_THROW(lu.compute(SparseMatrix(2, 3)), Error);
  lu.compute(random_general(10, 2, 21));
  EXPECT_THROW(lu.solve(Eigen::VectorXd::Ones(9)), Error);
}

}  // namespace
}  // namespace loom::numerics
