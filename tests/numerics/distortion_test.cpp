// Distortion of maps whose singular values are known in closed form.
#include <cmath>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "loom/numerics/distortion.hpp"
#include "test_meshes.hpp"

namespace loom::numerics {
namespace {

Eigen::MatrixX2d planar_uv(const Eigen::MatrixX3d& V, const Eigen::Matrix2d& A) {
  return (V.leftCols<2>() * A.transpose()).eval();
}

TEST(Distortion, IdentityMapIsUndistorted) {
  auto m = test::disk(6, 24);
  const Eigen::MatrixX2d UV = m.V.leftCols<2>();
  // The mesh rotated in space: its isometric frames are unchanged.
  m.V = (m.V * Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix().transpose()).eval();
  const DistortionReport r = distortion(m.V, m.F, UV);
  EXPECT_EQ(r.faces, m.F.rows());
  EXPECT_EQ(r.flipped, 0);
  EXPECT_NEAR(r.angle_mean, 1, 1e-12);
  EXPECT_NEAR(r.angle_max, 1, 1e-12);
  EXPECT_NEAR(r.area_mean, 1, 1e-12);
  EXPECT_NEAR(r.area_max, 1, 1e-12);
  EXPECT_NEAR(r.arap_energy, 0, 1e-20);
}

TEST(Distortion, UniformScaleAndRotationAreNormalizedAway) {
  const auto m = test::disk(6, 24);
  const Eigen::Matrix2d A = 3.5 * Eigen::Rotation2Dd(1.1).toRotationMatrix();
  const DistortionReport r = distortion(m.V, m.F, planar_uv(m.V, A));
  EXPECT_EQ(r.flipped, 0);
  EXPECT_NEAR(r.angle_max, 1, 1e-12);
  EXPECT_NEAR(r.area_max, 1, 1e-12);
  EXPECT_NEAR(r.arap_energy, 0, 1e-20);
}

TEST(Distortion, StretchHasKnownSingularValues) {
  // UV = (2x, y), rescaled to equal area: σ = (√2, 1/√2).
  const auto m = test::grid(5, 5);
  const DistortionReport r = distortion(m.V, m.F, planar_uv(m.V, Eigen::Vector2d(2, 1).asDiagonal()));
  EXPECT_EQ(r.flipped, 0);
  EXPECT_NEAR(r.angle_mean, 2, 1e-12);
  EXPECT_NEAR(r.angle_max, 2, 1e-12);
  EXPECT_NEAR(r.area_mean, 1, 1e-12);
  const double s1 = std::sqrt(2.0), s2 = 1 / s1;
  EXPECT_NEAR(r.arap_energy, (s1 - 1) * (s1 - 1) + (s2 - 1) * (s2 - 1), 1e-12);
}

TEST(Distortion, ReflectedMapIsAllFlipped) {
  const auto m = test::disk(6, 24);
  const DistortionReport r = distortion(m.V, m.F, planar_uv(m.V, Eigen::Vector2d(1, -1).asDiagonal()));
  EXPECT_EQ(r.flipped, m.F.rows());
  EXPECT_NEAR(r.angle_mean, 1, 1e-12);  // a reflection keeps angles' sizes
  EXPECT_NEAR(r.area_mean, 1, 1e-12);
  EXPECT_NEAR(r.arap_energy, 4, 1e-12);  // signed σ = (1, -1): distance² to the closest rotation
}

TEST(Distortion, CollapsedMapIsFlippedAndFinite) {
  const auto m = test::grid(4, 4);
  const DistortionReport r = distortion(m.V, m.F, Eigen::MatrixX2d::Zero(m.V.rows(), 2));
  EXPECT_EQ(r.flipped, m.F.rows());
  EXPECT_TRUE(std::isfinite(r.angle_mean) && std::isfinite(r.area_max) && std::isfinite(r.arap_energy));
  EXPECT_NEAR(r.arap_energy, 2, 1e-12);
}

TEST(Distortion, JsonAndLogLine) {
  const auto m = test::grid(2, 2);
  const DistortionReport r = distortion(m.V, m.F, m.V.leftCols<2>());
  const json j = to_json(r);
  EXPECT_EQ(j.at("faces"), 8);
  EXPECT_EQ(j.at("flipped"), 0);
  EXPECT_NEAR(j.at("angle_mean").get<double>(), 1, 1e-12);
  EXPECT_TRUE(j.contains("arap_energy") && j.contains("area_max") && j.contains("angle_max"));
  EXPECT_NE(to_string(r).find("0 flipped"), std::string::npos) << to_string(r);
}

}  // namespace
}  // namespace loom::numerics
