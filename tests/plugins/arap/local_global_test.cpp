// ARAP local/global: monotone energy, exact flattening of developable
// surfaces, planar meshes kept up to a rigid motion, the hybrid model's limit.
#include <cstdio>

#include <gtest/gtest.h>

#include "arap_test_meshes.hpp"
#include "local_global.hpp"
#include "similarity_map.hpp"
#include "tutte_map.hpp"

namespace loom::arap {
namespace {

ArapResult run_arap(const test::TestMesh& m, const Eigen::MatrixX2d& UV0, int iterations,
                    double tolerance, double lambda = -1, int anderson = ArapOptions().anderson) {
  const ArapSystem sys = arap_system(m.V, m.F, {});
  ArapOptions o;
  o.max_iterations = iterations;
  o.tolerance = tolerance;
  o.lambda = lambda;
  o.anderson = anderson;
  return arap(sys, UV0, o);
}

Eigen::MatrixX2d asap_uv(const test::TestMesh& m) {
  return similarity_map(triangle_frames(m.V, m.F), m.F, int(m.V.rows()), similarity_pins(m.V, m.F, {})).UV;
}

TEST(LocalGlobal, EnergyNeverIncreases) {
  const auto m = test::cap(10, 32);
  for (double lambda : {-1.0, 0.05, 10.0}) {
    const ArapResult r = run_arap(m, tutte_map(m.V, m.F), 150, 0, lambda);
    ASSERT_GE(r.energy.size(), 10u);  // tolerance 0: runs until the energy stops falling
    for (size_t k = 1; k < r.energy.size(); ++k)
      EXPECT_LE(r.energy[k], r.energy[k - 1] * (1 + 1e-12)) << "iteration " << k << " lambda " << lambda;
    EXPECT_LT(r.energy.back(), 0.5 * r.energy.front());
    // The reported energy is the local step's own: E(u) with the best L.
    EXPECT_NEAR(r.energy.back(), local_global_energy(triangle_frames(m.V, m.F), m.F, r.UV, lambda),
                1e-12 * r.energy.back());
  }
}

// An accordion: the unit square folded along vertex columns, each triangle
// moved rigidly, so the surface is isometric to the square.
test::TestMesh folded_sheet(const test::TestMesh& flat, int n) {
  test::TestMesh m = flat;
  const double angles[3] = {0, 2.2, 0.4};
  const int folds[2] = {n / 3, 2 * n / 3};
  for (Eigen::Index v = 0; v < m.V.rows(); ++v) {
    const double x = flat.V(v, 0), y = flat.V(v, 1);
    double px = 0, pz = 0, start = 0;
    for (int s = 0; s < 3; ++s) {
      const double end = s < 2 ? double(folds[s]) / n : 1.0;
      const double len = std::min(x, end) - start;
      if (len <= 0) break;
      px += len * std::cos(angles[s]), pz += len * std::sin(angles[s]);
      start = end;
    }
    m.V.row(v) << px, y, pz;
  }
  return m;
}

TEST(LocalGlobal, FoldedSheetFlattensToItsOriginalShape) {
  const int n = 12;
  const auto flat = test::irregular_grid(n, 5, false);
  // Only the folds must lie on vertex columns: keep those columns straight.
  auto flat_cols = flat;
  for (Eigen::Index v = 0; v < flat.V.rows(); ++v) {
    const int i = int(v % (n + 1));
    if (i == n / 3 || i == 2 * n / 3) flat_cols.V(v, 0) = double(i) / n;
  }
  const auto m = folded_sheet(flat_cols, n);
  const ArapResult r = run_arap(m, asap_uv(m), 2000, 1e-14);
  EXPECT_LT(r.energy.back(), 1e-16 * r.energy.front() + 1e-20);
  EXPECT_LT(test::edge_length_error(m, r.UV), 1e-7);
  EXPECT_LT(test::fit_residual(flat_cols.V.leftCols<2>(), r.UV, false), 1e-7);
}

TEST(LocalGlobal, RolledSheetFlattensWithExactEdgeLengths) {
  // A sheet rolled onto a cylinder along vertex columns (rulings): a prism,
  // isometric to the flat strip of chord-wide columns.
  const int nx = 24, ny = 6;
  test::TestMesh m = numerics::test::grid(nx, ny);
  const double R = 0.3, span = 1.5 * M_PI;
  for (Eigen::Index v = 0; v < m.V.rows(); ++v) {
    const double th = m.V(v, 0) * span;
    m.V.row(v) << R * std::sin(th), m.V(v, 1), R * (1 - std::cos(th));
  }
  const ArapResult r = run_arap(m, tutte_map(m.V, m.F), 3000, 1e-14);
  EXPECT_LT(r.energy.back(), 1e-16 * r.energy.front() + 1e-20);
  EXPECT_LT(test::edge_length_error(m, r.UV), 1e-7);
}

TEST(LocalGlobal, PlanarMeshIsReproducedUpToARigidMotion) {
  const auto flat = test::irregular_grid(16, 2, false);
  const auto tilted = test::irregular_grid(16, 2, true);
  const ArapResult r = run_arap(tilted, tutte_map(tilted.V, tilted.F), 3000, 1e-14);
  EXPECT_LT(test::fit_residual(flat.V.leftCols<2>(), r.UV, false), 1e-7);
  EXPECT_LT(test::edge_length_error(tilted, r.UV), 1e-6);
}

TEST(LocalGlobal, HybridWithLargeLambdaApproachesArap) {
  const auto m = test::cap(8, 24);
  const Eigen::MatrixX2d UV0 = asap_uv(m);
  const ArapResult arap_r = run_arap(m, UV0, 300, 0);
  const ArapResult hybrid = run_arap(m, UV0, 300, 0, 1e7);
  EXPECT_LT((arap_r.UV - hybrid.UV).norm() / arap_r.UV.norm(), 1e-4);
}

TEST(LocalGlobal, ToleranceStopsEarly) {
  const auto m = test::cap(6, 16);
  const ArapResult r = run_arap(m, asap_uv(m), 1000, 1e-3);
  EXPECT_TRUE(r.converged);
  EXPECT_LT(r.iterations, 1000);
  const double last = r.energy[r.energy.size() - 2] - r.energy.back();
  EXPECT_LE(last, 1e-3 * r.energy[r.energy.size() - 2]);
}

// Anderson acceleration changes the path, not the answer: against the plain
// local/global iteration (the reference, anderson = 0) run to a tight
// tolerance, the accelerated run reaches the same energy and shape in fewer
// iterations, and its energy never increases on the way.
TEST(LocalGlobal, AndersonAccelerationReachesThePlainIterationsMinimumSooner) {
  const auto m = test::cap(10, 32);
  for (double lambda : {-1.0, 10.0}) {
    const Eigen::MatrixX2d UV0 = tutte_map(m.V, m.F);
    const ArapResult plain = run_arap(m, UV0, 5000, 1e-13, lambda, 0);
    const ArapResult fast = run_arap(m, UV0, 5000, 1e-13, lambda, 5);
    ASSERT_TRUE(plain.converged && fast.converged) << lambda;
    EXPECT_LT(fast.iterations, plain.iterations) << lambda;
    EXPECT_NEAR(fast.energy.back(), plain.energy.back(), 1e-8 * plain.energy.back()) << lambda;
    // E is blind to a rotation about the pinned vertex: compare the maps up
    // to a rigid motion.
    EXPECT_LT(test::fit_residual(plain.UV, fast.UV, false), 1e-5) << lambda;
    for (size_t k = 1; k < fast.energy.size(); ++k)
      EXPECT_LE(fast.energy[k], fast.energy[k - 1]) << "iteration " << k << " lambda " << lambda;
    std::printf("lambda %g: %d iterations plain, %d accelerated\n", lambda, plain.iterations, fast.iterations);
  }
}

}  // namespace
}  // namespace loom::arap
