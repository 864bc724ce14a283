// Denoising by displacement map against a clean generated surface with
// seeded noise, and the baking against analytic functions.
#include <gtest/gtest.h>

#include <random>

#include "mesh_denoising.hpp"
#include "shading_scenes.hpp"
#include "loom/numerics/tangent_frames.hpp"

namespace loom::shading {
namespace {

TEST(MeshDenoising, DisplacementIsTheNormalPartOfTheUmbrella) {
  // A vertex lifted by h above the centre of a flat fan of 6 neighbours:
  // δ = (0, 0, h), the normal is +z, so d = h.
  Eigen::MatrixX3d V(7, 3);
  V.row(0) << 0, 0, 0.1;
  for (int k = 0; k < 6; ++k) V.row(k + 1) << std::cos(k * M_PI / 3), std::sin(k * M_PI / 3), 0;
  Eigen::MatrixX3i F(6, 3);
  for (int k = 0; k < 6; ++k) F.row(k) << 0, 1 + k, 1 + (k + 1) % 6;
  Eigen::MatrixX3d N = Eigen::MatrixX3d::Zero(7, 3);
  N.col(2).setOnes();
  const Eigen::VectorXd d = normal_displacements(V, F, N);
  EXPECT_NEAR(d(0), 0.1, 1e-12);
  for (int k = 1; k < 7; ++k) EXPECT_EQ(d(k), 0.0);  // boundary
}

TEST(MeshDenoising, BakingReproducesASmoothFunctionAtTheVertices) {
  const Mesh grid = scenes::plane(60, 1);
  Eigen::VectorXd d(grid.V.rows());
  for (Eigen::Index i = 0; i < d.size(); ++i) d(i) = 0.3 * grid.UV(i, 0) * grid.UV(i, 0) - 0.2 * grid.UV(i, 1);
  const DisplacementMap map = bake_displacement(grid.UV, d, 256, 4);
  double lo, hi;
  cv::minMaxLoc(map.image, &lo, &hi);
  EXPECT_NEAR(lo, 0.0, 1e-6);
  EXPECT_NEAR(hi, 1.0, 1e-6);
  const Eigen::VectorXd back = sample_displacement(map, grid.UV);
  EXPECT_LT((back - d).cwiseAbs().maxCoeff(), 0.01 * (d.maxCoeff() - d.minCoeff()));
}

Mesh wavy_surface(int n) {
  Mesh m = scenes::plane(n, 1);
  for (Eigen::Index i = 0; i < m.V.rows(); ++i)
    m.V(i, 1) = 0.15 * std::sin(M_PI * m.V(i, 0)) * std::sin(M_PI * m.V(i, 2));
  return m;
}

TEST(MeshDenoising, RemovesMostOfTheNoiseOfAGentleSurface) {
  const Mesh clean = wavy_surface(80);
  Mesh noisy = clean;
  const Eigen::MatrixX3d N = numerics::vertex_normals(clean.V, clean.F);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> gauss(0, 0.004);
  for (Eigen::Index i = 0; i < noisy.V.rows(); ++i) noisy.V.row(i) += gauss(rng) * N.row(i);
  const SurfaceError before = surface_error(noisy.V, clean.V, clean.F);

  const Eigen::MatrixX3d Nn = numerics::vertex_normals(noisy.V, noisy.F);
  const DisplacementMap map = bake_displacement(noisy.UV, normal_displacements(noisy.V, noisy.F, Nn), 512, 4);
  const Eigen::MatrixX3d denoised = remove_displacement(noisy.V, Nn, sample_displacement(map, noisy.UV));
  const SurfaceError after = surface_error(denoised, clean.V, clean.F);
  EXPECT_LT(after.rms_distance, 0.7 * before.rms_distance) << before.rms_distance << " -> " << after.rms_distance;
  EXPECT_LT(after.mean_normal_angle, 0.6 * before.mean_normal_angle)
      << before.mean_normal_angle << " -> " << after.mean_normal_angle;

  // The smoothing flows also improve on the noise, and keep the boundary.
  for (SmoothingWeights w : {SmoothingWeights::uniform, SmoothingWeights::cotangent}) {
    const Eigen::MatrixX3d s = smooth(noisy.V, noisy.F, w, 3, 0.5);
    EXPECT_LT(surface_error(s, clean.V, clean.F).mean_normal_angle, before.mean_normal_angle);
    EXPECT_EQ(s.row(0), noisy.V.row(0));
  }
}

}  // namespace
}  // namespace loom::shading
