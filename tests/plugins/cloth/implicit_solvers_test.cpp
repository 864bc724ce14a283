// Newton and local/global minimize the same incremental potential: they agree
// with each other, keep linear momentum, and match the closed-form implicit
// Euler solution of a single spring.
#include <cmath>

#include <gtest/gtest.h>

#include "cloth_test_systems.hpp"
#include "implicit_solvers.hpp"
#include "incremental_potential.hpp"
#include "time_step.hpp"

namespace loom::cloth {
namespace {

// The inertial target of one step from rest under gravity.
Eigen::MatrixX3d target(const SpringSystem& s, const Eigen::MatrixX3d& x, const Eigen::MatrixX3d& v, double h,
                        const Eigen::Vector3d& g) {
  Eigen::MatrixX3d y = x;
  for (int i = 0; i < s.vertices(); ++i)
    if (!s.fixed[i]) y.row(i) += h * v.row(i) + h * h * g.transpose();
  return y;
}

// The target of a step of a cloth swinging out of its plane (v_z = sin 5x,
// the fixed vertices still), under gravity: springs stretched and compressed.
Eigen::MatrixX3d swinging_target(const SpringSystem& s, double h) {
  Eigen::MatrixX3d v = Eigen::MatrixX3d::Zero(s.vertices(), 3);
  for (int i = 0; i < s.vertices(); ++i)
    if (!s.fixed[i]) v(i, 2) = std::sin(5 * s.X(i, 0));
  return target(s, s.X, v, h, Eigen::Vector3d(0, -9.81, 0));
}

TEST(ImplicitSolvers, NewtonAndLocalGlobalConvergeToTheSameStep) {
  // Local/global converges linearly, slowly for stiff springs on light
  // masses: k = 100 lets it reach 1e-12 in tens of thousands of iterations.
  const SpringSystem s = test::curtain(10, 100);
  const double h = 1.0 / 30;
  // A swinging start so the springs are stretched and compressed.
  Eigen::MatrixX3d v = Eigen::MatrixX3d::Zero(s.vertices(), 3);
  for (int i = 0; i < s.vertices(); ++i)
    if (!s.fixed[i]) v.row(i) << 0, 0, 0.3 * std::sin(7 * s.X(i, 0)) * (0.5 - s.X(i, 1));
  const Eigen::MatrixX3d y = target(s, s.X, v, h, Eigen::Vector3d(0, -9.81, 0));

  SolveOptions tight;
  tight.iterations = 100;
  tight.tolerance = 0;  // to machine precision: stops when no step decreases E
  SolveReport newton_report;
  const Eigen::MatrixX3d xn = newton_solve(s, y, h, y, tight, &newton_report);
  EXPECT_TRUE(newton_report.converged);
  // The floor is rounding: 1e-12 with multithreaded BLAS, 3.7e-12 with
  // OPENBLAS_NUM_THREADS=1 (another summation order).
  EXPECT_LT(newton_report.residuals.back(), 1e-11);

  SolveOptions lg_options;
  lg_options.iterations = 200000;
  lg_options.tolerance = 1e-12;
  SolveReport lg_report;
  const LocalGlobalSolver lg(s, h);
  const Eigen::MatrixX3d xl = lg.solve(s, y, y, lg_options, &lg_report);
  EXPECT_TRUE(lg_report.converged);
  const double relative = (xn - xl).norm() / xn.norm();
  EXPECT_LT(relative, 1e-8) << "local/global iterations: " << lg_report.iterations;
  // Both are minimizers: the gradient vanishes.
  EXPECT_LT(incremental_gradient(s, xn, y, h).norm(), 1e-10 * incremental_gradient(s, y, y, h).norm());
  // The scale each report's residuals are relative to: the start's gradient.
  EXPECT_EQ(newton_report.start_gradient, incremental_gradient(s, y, y, h).norm());
  EXPECT_EQ(lg_report.start_gradient, incremental_gradient(s, y, y, h).norm());
  SolveOptions one;
  one.iterations = 1;
  SolveReport from_newton;
  lg.solve(s, y, xn, one, &from_newton);
  EXPECT_EQ(from_newton.start_gradient, incremental_gradient(s, xn, y, h).norm());
}

TEST(ImplicitSolvers, LocalGlobalDecreasesThePotentialEveryIteration) {
  const SpringSystem s = test::curtain(12, 1e5);
  const double h = 1.0 / 30;
  const Eigen::MatrixX3d y = target(s, s.X, Eigen::MatrixX3d::Zero(s.vertices(), 3), h, Eigen::Vector3d(0, -9.81, 0));
  const LocalGlobalSolver lg(s, h);
  double previous = incremental_potential(s, y, y, h);
  Eigen::MatrixX3d x = y;
  SolveOptions one;
  one.iterations = 1;
  for (int it = 0; it < 30; ++it) {
    x = lg.solve(s, y, x, one);
    const double e = incremental_potential(s, x, y, h);
    EXPECT_LE(e, previous * (1 + 1e-14)) << "iteration " << it;
    previous = e;
  }
}

// Anderson acceleration (Peng et al. 2018, window 6) of local/global on a
// stiff (k = 1e5) 15² curtain of 1000 kg/m², swinging: it reaches the step's
// minimizer, Newton's run to a relative gradient of 1e-11, in a fraction of
// the iterations the plain iteration does not converge in (measured: 312
// against > 3000, where plain is at 5.6e-8). On the light (0.1 kg/m²)
// curtain it stalls near 1e-5 (docs/cloth.md): not tested here.
TEST(ImplicitSolvers, AndersonConvergesToNewtonsMinimizer) {
  SpringSystem s = grid_cloth(15, 15, Eigen::Vector3d(-0.5, -0.5, 0), Eigen::Vector3d(1, 0, 0),
                              Eigen::Vector3d(0, 1, 0), 1000, 1e5, 1e5, 1e5);
  fix_vertices(s, {}, Eigen::Vector3d(-1, 0.49, -1), Eigen::Vector3d(1, 1, 1));
  const double h = 1.0 / 30;
  const Eigen::MatrixX3d y = swinging_target(s, h);
  SolveOptions tight;
  tight.iterations = 500;
  tight.tolerance = 1e-11;
  SolveReport newton_report;
  const Eigen::MatrixX3d reference = newton_solve(s, y, h, y, tight, &newton_report);
  ASSERT_TRUE(newton_report.converged) << newton_report.residuals.back();
  const LocalGlobalSolver lg(s, h);
  SolveOptions options;
  options.iterations = 2000;
  options.tolerance = 1e-11;
  options.anderson = 6;
  SolveReport anderson, plain;
  const Eigen::MatrixX3d xa = lg.solve(s, y, y, options, &anderson);
  ASSERT_TRUE(anderson.converged) << anderson.residuals.back();
  EXPECT_LT((xa - reference).norm() / (reference - y).norm(), 1e-8) << anderson.iterations << " iterations";
  options.anderson = 0;
  lg.solve(s, y, y, options, &plain);
  EXPECT_LT(3 * anderson.iterations, plain.iterations) << "plain reached " << plain.residuals.back();
}

// The safeguard: every accepted iterate lowers E (the springs' and
// inertia's, recomputed here from the final positions for the last one),
// though the extrapolation alone does not (some iterates were rejected).
TEST(ImplicitSolvers, AndersonSafeguardKeepsThePotentialMonotone) {
  const SpringSystem s = test::curtain(20, 1e5);
  const double h = 1.0 / 30;
  const Eigen::MatrixX3d y = swinging_target(s, h);
  const LocalGlobalSolver lg(s, h);
  SolveOptions options;
  options.iterations = 300;
  options.anderson = 6;
  SolveReport report;
  const Eigen::MatrixX3d x = lg.solve(s, y, y, options, &report);
  ASSERT_EQ(report.energies.size(), 301u);
  EXPECT_GT(report.rejected, 0);
  for (std::size_t k = 1; k < report.energies.size(); ++k)
    EXPECT_LE(report.energies[k], report.energies[k - 1]) << "iteration " << k;
  EXPECT_NEAR(report.energies.front(), incremental_potential(s, y, y, h), 1e-12 * report.energies.front());
  EXPECT_NEAR(report.energies.back(), incremental_potential(s, x, y, h), 1e-12 * report.energies.front());
}

// Chebyshev acceleration (Wang 2015) at its default ρ = 0.99, on a swinging
// k = 1e5 curtain: closer to the converged (Newton) step after 100 iterations (measured:
// 0.015 against 0.022; bench/cloth has the full curves).
TEST(ImplicitSolvers, ChebyshevGetsCloserInTheSameIterations) {
  const SpringSystem s = test::curtain(20, 1e5);
  const double h = 1.0 / 30;
  const Eigen::MatrixX3d y = swinging_target(s, h);
  SolveOptions tight;
  tight.iterations = 100;
  const Eigen::MatrixX3d reference = newton_solve(s, y, h, y, tight);
  const LocalGlobalSolver lg(s, h);
  SolveOptions plain;
  plain.iterations = 100;
  SolveOptions cheb = plain;
  cheb.chebyshev = true;
  const double error_plain = (lg.solve(s, y, y, plain) - reference).norm() / reference.norm();
  const Eigen::MatrixX3d xc = lg.solve(s, y, y, cheb);
  ASSERT_TRUE(xc.allFinite());
  const double error_cheb = (xc - reference).norm() / reference.norm();
  EXPECT_LT(error_cheb, 0.8 * error_plain) << "plain " << error_plain << ", Chebyshev " << error_cheb;
}

// With no gravity, damping or fixed points, Σ m v is conserved: internal
// forces cancel in pairs and both solvers keep 1ᵀM(x − y) = 0 exactly.
TEST(ImplicitSolvers, LinearMomentumIsConserved) {
  SpringSystem s = test::curtain(8, 1e4, false);
  std::srand(3);
  Eigen::MatrixX3d x = s.X + 0.05 * Eigen::MatrixX3d::Random(s.vertices(), 3);
  Eigen::MatrixX3d v = Eigen::MatrixX3d::Random(s.vertices(), 3);
  const auto system = test::shared(s);
  for (Solver solver : {Solver::newton, Solver::local_global}) {
    ClothState state{system, x, v, 0};
    StepSettings settings;
    settings.solver = solver;
    settings.gravity.setZero();
    settings.solve.iterations = solver == Solver::newton ? 5 : 10;
    const LocalGlobalSolver lg(*system, 0.01);
    const Eigen::RowVector3d p0 = system->mass.transpose() * state.v;
    for (int n = 0; n < 20; ++n) {
      const Eigen::RowVector3d before = system->mass.transpose() * state.v;
      state = step(state, 0.01, settings, &lg).state;
      const Eigen::RowVector3d after = system->mass.transpose() * state.v;
      EXPECT_LT((after - before).norm(), 1e-10 * p0.norm()) << "step " << n;
    }
  }
}

// One free mass on a spring to a fixed point, moving along the spring's axis
// (so the spring is exactly linear): implicit Euler's closed form
//   v_{n+1} = (e^{−ch} v_n − h ω² u_n) / (1 + h² ω²),  u_{n+1} = u_n + h v_{n+1}
// with u the stretch and ω² = k/m.
TEST(ImplicitSolvers, SingleSpringMatchesTheDampedOscillator) {
  SpringSystem s;
  s.X.resize(2, 3);
  s.X << 0, 0, 0, 1, 0, 0;
  s.springs.resize(1, 2);
  s.springs << 0, 1;
  s.rest_length.resize(1);
  s.rest_length << 1;
  s.stiffness.resize(1);
  s.stiffness << 400;
  s.mass.resize(2);
  s.mass << 1, 4;
  s.fixed.resize(2);
  s.fixed << 1, 0;
  const auto system = test::shared(s);
  const double h = 1e-3, c = 0.5, w2 = 400 / 4.0, amplitude = 0.1;
  for (Solver solver : {Solver::newton, Solver::local_global}) {
    StepSettings settings;
    settings.solver = solver;
    settings.gravity.setZero();
    settings.damping = c;
    settings.solve.iterations = solver == Solver::newton ? 20 : 5000;
    settings.solve.tolerance = 1e-14;
    const LocalGlobalSolver lg(*system, h);
    ClothState state = rest_state(system);
    state.x(1, 0) += amplitude;
    double u = amplitude, v = 0;
    for (int n = 0; n < 1000; ++n) {
      state = step(state, h, settings, &lg).state;
      v = (std::exp(-c * h) * v - h * w2 * u) / (1 + h * h * w2);
      u += h * v;
    }
    EXPECT_NEAR(state.x(1, 0) - 1, u, 1e-10);
    EXPECT_NEAR(state.v(1, 0), v, 1e-8);
    EXPECT_NEAR(state.x(1, 1), 0, 1e-14);
    // And close to the continuous damped oscillator u(t) = A e^{−ct/2} cos(ω_d t)
    // (plus the sin term), within implicit Euler's O(h) error: its amplitude
    // decays by (1 + h²ω²)^{−n/2} ≈ e^{−hω²t/2} per unit amplitude.
    const double t = 1, wd = std::sqrt(w2 - c * c / 4);
    const double exact = amplitude * std::exp(-c * t / 2) * (std::cos(wd * t) + c / (2 * wd) * std::sin(wd * t));
    EXPECT_NEAR(state.x(1, 0) - 1, exact, 0.6 * h * w2 * t * amplitude);
  }
}

}  // namespace
}  // namespace loom::cloth
