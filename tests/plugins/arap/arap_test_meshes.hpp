// Meshes and measures shared by the arap tests.
#pragma once

#include <cmath>
#include <random>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "test_meshes.hpp"

namespace loom::arap::test {

using numerics::test::TestMesh;

// A grid with its interior vertices jittered in the plane (irregular, with
// obtuse triangles), then, if `tilt`, moved rigidly onto a tilted plane.
inline TestMesh irregular_grid(int n, unsigned seed, bool tilt) {
  TestMesh m = numerics::test::grid(n, n);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.3 / n, 0.3 / n);
  for (int j = 1; j < n; ++j)
    for (int i = 1; i < n; ++i) {
      auto row = m.V.row(j * (n + 1) + i);
      row(0) += jitter(rng), row(1) += jitter(rng);
    }
  if (!tilt) return m;
  Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  m.V = (m.V * R.transpose()).rowwise() + Eigen::RowVector3d(0.3, -1, 2);
  return m;
}

// A half-open hemisphere-like cap: z = sqrt(1 − r²) over a disk of radius 0.9.
inline TestMesh cap(int rings, int segments) {
  TestMesh m = numerics::test::disk(rings, segments);
  for (Eigen::Index v = 0; v < m.V.rows(); ++v) {
    m.V.row(v).head<2>() *= 0.9;
    m.V(v, 2) = std::sqrt(1 - m.V.row(v).head<2>().squaredNorm());
  }
  return m;
}

// Residual of the best fit P ≈ s R Q + t (Umeyama), relative to the size of P;
// with_scale = false fits a rigid motion. Q, P #V by 2.
inline double fit_residual(const Eigen::MatrixX2d& Q, const Eigen::MatrixX2d& P, bool with_scale,
                           double* scale = nullptr) {
  const Eigen::RowVector2d cq = Q.colwise().mean(), cp = P.colwise().mean();
  const Eigen::MatrixX2d q = Q.rowwise() - cq, p = P.rowwise() - cp;
  Eigen::JacobiSVD<Eigen::Matrix2d> svd(p.transpose() * q, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix2d D = Eigen::Matrix2d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) D(1, 1) = -1;
  const Eigen::Matrix2d R = svd.matrixU() * D * svd.matrixV().transpose();
  const double s = with_scale ? (svd.singularValues().asDiagonal() * D).trace() / q.squaredNorm() : 1;
  if (scale) *scale = s;
  return (p - s * q * R.transpose()).norm() / p.norm();
}

// The largest relative difference between edge lengths in 3D and in UV.
inline double edge_length_error(const TestMesh& m, const Eigen::MatrixX2d& UV) {
  double worst = 0;
  for (Eigen::Index t = 0; t < m.F.rows(); ++t)
    for (int i = 0; i < 3; ++i) {
      const int a = m.F(t, i), b = m.F(t, (i + 1) % 3);
      const double l3 = (m.V.row(a) - m.V.row(b)).norm(), l2 = (UV.row(a) - UV.row(b)).norm();
      worst = std::max(worst, std::abs(l3 - l2) / l3);
    }
  return worst;
}

}  // namespace loom::arap::test
