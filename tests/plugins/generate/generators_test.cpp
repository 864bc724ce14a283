// The generators against closed-form shapes: areas and volumes of the
// inscribed polygons and polyhedra, Euler characteristics, boundary loops,
// orientation, and the seeded noise of the hemisphere.
#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "generators.hpp"
#include "loom/error.hpp"
#include "loom/numerics/mesh_topology.hpp"

namespace loom::generate {
namespace {

// Twice the signed area of each triangle's projection onto the xy plane.
Eigen::VectorXd signed_areas2(const Mesh& m) {
  Eigen::VectorXd a(m.F.rows());
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector3d p = m.V.row(m.F(f, 0)), q = m.V.row(m.F(f, 1)), r = m.V.row(m.F(f, 2));
    a[f] = (q - p).cross(r - p).z();
  }
  return a;
}

// V − E + F.
long euler_characteristic(const Mesh& m) {
  std::set<std::pair<int, int>> edges;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = m.F(f, k), b = m.F(f, (k + 1) % 3);
      edges.emplace(std::min(a, b), std::max(a, b));
    }
  return static_cast<long>(m.V.rows()) - static_cast<long>(edges.size()) + static_cast<long>(m.F.rows());
}

// Volume enclosed by a closed, outward-oriented mesh (divergence theorem).
double volume(const Mesh& m) {
  double v = 0;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector3d p = m.V.row(m.F(f, 0)), q = m.V.row(m.F(f, 1)), r = m.V.row(m.F(f, 2));
    v += p.dot(q.cross(r)) / 6;
  }
  return v;
}

TEST(Generators, GridCoversItsRectangleCounterClockwise) {
  const Mesh m = grid_mesh(5, 3, [](double u, double v) { return Eigen::Vector3d(2 * u, 0.5 * v, 0); });
  EXPECT_EQ(m.V.rows(), 6 * 4);
  EXPECT_EQ(m.F.rows(), 2 * 5 * 3);
  const Eigen::VectorXd a = signed_areas2(m);
  EXPECT_GT(a.minCoeff(), 0);
  EXPECT_NEAR(a.sum() / 2, 1.0, 1e-14);
  EXPECT_EQ(euler_characteristic(m), 1);
  const auto loops = numerics::boundary_loops(m.F);
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops[0].size(), 2u * (5 + 3));
  // Vertex (i, j) is row j·(nx+1) + i, with UV (i/nx, j/ny).
  EXPECT_EQ(m.UV.row(2 * 6 + 4), Eigen::RowVector2d(4.0 / 5, 2.0 / 3));
  EXPECT_EQ(m.V.row(2 * 6 + 4), Eigen::RowVector3d(2 * (4.0 / 5), 0.5 * (2.0 / 3), 0));
}

TEST(Generators, GridCellsLeftOutAreHoles) {
  const Mesh m = grid_mesh(4, 4, [](double u, double v) { return Eigen::Vector3d(u, v, 0); },
                           [](int i, int j) { return !(i == 1 && j == 2); });
  EXPECT_EQ(m.V.rows(), 25);
  EXPECT_EQ(m.F.rows(), 2 * 15);
  EXPECT_NEAR(signed_areas2(m).sum() / 2, 15.0 / 16, 1e-14);
  EXPECT_EQ(numerics::boundary_loops(m.F).size(), 2u);
  EXPECT_EQ(euler_characteristic(m), 0);
}

TEST(Generators, RectangleIsCenteredWithUnitUVs) {
  const Mesh m = rectangle_mesh(Vec2(3, 2), 6, 4);
  EXPECT_EQ(m.V.colwise().minCoeff(), Eigen::RowVector3d(-1.5, -1, 0));
  EXPECT_EQ(m.V.colwise().maxCoeff(), Eigen::RowVector3d(1.5, 1, 0));
  EXPECT_EQ(m.UV.colwise().minCoeff(), Eigen::RowVector2d(0, 0));
  EXPECT_EQ(m.UV.colwise().maxCoeff(), Eigen::RowVector2d(1, 1));
  EXPECT_NEAR(signed_areas2(m).sum() / 2, 6.0, 1e-13);
}

TEST(Generators, FlatDiskIsTheInscribedPolygon) {
  // Area of the regular n-gon inscribed in the circle of radius R: n/2 R² sin(2π/n).
  const int n = 40;
  const double R = 2.5;
  const Mesh m = disk_mesh(R, 7, n, 0);
  EXPECT_EQ(m.V.rows(), 1 + 7 * n);
  EXPECT_EQ(m.F.rows(), n * (2 * 7 - 1));
  const Eigen::VectorXd a = signed_areas2(m);
  EXPECT_GT(a.minCoeff(), 0);
  EXPECT_NEAR(a.sum() / 2, n / 2.0 * R * R * std::sin(2 * M_PI / n), 1e-12);
  EXPECT_EQ(euler_characteristic(m), 1);
  const auto loops = numerics::boundary_loops(m.F);
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops[0].size(), static_cast<size_t>(n));
  for (int v : loops[0]) EXPECT_NEAR(m.V.row(v).norm(), R, 1e-14);
  EXPECT_EQ(m.V.col(2).cwiseAbs().maxCoeff(), 0.0);
}

TEST(Generators, BumpyDiskKeepsAFlatBoundaryAndFollowsItsHeightField) {
  const double R = 1.5, h = 0.2;
  const Mesh m = disk_mesh(R, 10, 48, h);
  const auto loops = numerics::boundary_loops(m.F);
  ASSERT_EQ(loops.size(), 1u);
  for (int v : loops[0]) EXPECT_NEAR(m.V(v, 2), 0.0, 1e-15);
  for (Eigen::Index v = 0; v < m.V.rows(); ++v) {
    const double x = m.V(v, 0), y = m.V(v, 1), r2 = (x * x + y * y) / (R * R);
    EXPECT_NEAR(m.V(v, 2), h * std::sin(2 * M_PI * x / R) * std::sin(2 * M_PI * y / R) * (1 - r2), 1e-14);
  }
}

TEST(Generators, SphereIsClosedOutwardAndOnItsRadius) {
  const double R = 1.7;
  const int rings = 24, segments = 48;
  const Mesh m = uv_sphere_mesh(R, rings, segments);
  EXPECT_EQ(m.V.rows(), 2 + (rings - 1) * segments);
  EXPECT_EQ(euler_characteristic(m), 2);
  EXPECT_TRUE(numerics::boundary_loops(m.F).empty());
  for (Eigen::Index v = 0; v < m.V.rows(); ++v) EXPECT_NEAR(m.V.row(v).norm(), R, 1e-14);
  EXPECT_LT((m.N - m.V / R).cwiseAbs().maxCoeff(), 1e-15);
  // Convex and inscribed: it lies inside the ball and contains the ball whose
  // radius is its nearest face plane's distance, so its volume (positive:
  // outward faces) lies between theirs.
  double nearest = R;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector3d p = m.V.row(m.F(f, 0)), q = m.V.row(m.F(f, 1)), r = m.V.row(m.F(f, 2));
    nearest = std::min(nearest, std::abs((q - p).cross(r - p).normalized().dot(p)));
  }
  const double v = volume(m);
  EXPECT_LT(v, 4.0 / 3 * M_PI * R * R * R);
  EXPECT_GT(v, 4.0 / 3 * M_PI * std::pow(nearest, 3));
  EXPECT_GT(nearest, R * std::cos(M_PI / rings));
}

TEST(Generators, HemisphereHasTheEquatorAsItsBoundary) {
  std::mt19937_64 rng(1);
  const double R = 0.8;
  const Mesh m = hemisphere_mesh(R, 12, 36, 0, rng);
  EXPECT_EQ(euler_characteristic(m), 1);
  for (Eigen::Index v = 0; v < m.V.rows(); ++v) {
    EXPECT_NEAR(m.V.row(v).norm(), R, 1e-14);
    EXPECT_GE(m.V(v, 2), -1e-15);
  }
  const auto loops = numerics::boundary_loops(m.F);
  ASSERT_EQ(loops.size(), 1u);
  for (int v : loops[0]) EXPECT_NEAR(m.V(v, 2), 0.0, 1e-15);
  EXPECT_EQ(m.V.row(0), Eigen::RowVector3d(0, 0, R));
  // Seen from +z the projection is the inscribed 36-gon, counter-clockwise.
  EXPECT_NEAR(signed_areas2(m).sum() / 2, 18 * R * R * std::sin(2 * M_PI / 36), 1e-13);
}

TEST(Generators, HemisphereNoiseIsRadialBoundedAndSeeded) {
  const double R = 2, noise = 0.1;
  std::mt19937_64 a(5), b(5), c(6);
  const Mesh ma = hemisphere_mesh(R, 8, 24, noise, a), mb = hemisphere_mesh(R, 8, 24, noise, b);
  const Mesh mc = hemisphere_mesh(R, 8, 24, noise, c);
  EXPECT_EQ(ma.V, mb.V);
  EXPECT_GT((ma.V - mc.V).norm(), 0.1);
  std::mt19937_64 quiet(5);
  const Mesh smooth = hemisphere_mesh(R, 8, 24, 0, quiet);
  for (Eigen::Index v = 0; v < ma.V.rows(); ++v) {
    const double r = ma.V.row(v).norm();
    EXPECT_LE(std::abs(r / R - 1), noise + 1e-15);
    // Along the same direction as the smooth hemisphere's vertex.
    EXPECT_NEAR(ma.V.row(v).dot(smooth.V.row(v)) / (r * R), 1.0, 1e-14);
  }
}

TEST(Generators, CheckerboardCornerSquareHasColorA) {
  const Color a{{1, 0, 0, 1}}, b{{0, 0, 1, 1}};
  const cv::Mat m = checkerboard(Vec2i(30, 20), 4, a, b);  // cells of 5 pixels
  ASSERT_EQ(m.type(), CV_32FC3);
  EXPECT_EQ(m.cols, 30);
  EXPECT_EQ(m.rows, 20);
  EXPECT_EQ(m.at<cv::Vec3f>(0, 0), cv::Vec3f(1, 0, 0));
  EXPECT_EQ(m.at<cv::Vec3f>(4, 4), cv::Vec3f(1, 0, 0));
  EXPECT_EQ(m.at<cv::Vec3f>(0, 5), cv::Vec3f(0, 0, 1));
  EXPECT_EQ(m.at<cv::Vec3f>(5, 0), cv::Vec3f(0, 0, 1));
  EXPECT_EQ(m.at<cv::Vec3f>(19, 29), cv::Vec3f(1, 0, 0));  // cell (5, 3): an even sum, color a
}

TEST(Generators, BadCountsAreClearErrors) {
  auto message = [](auto&& f) {
    try {
      f();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_NE(message([] { disk_mesh(1, 0, 8, 0); }).find("rings"), std::string::npos);
  EXPECT_NE(message([] { disk_mesh(1, 4, 2, 0); }).find("segments"), std::string::npos);
  EXPECT_NE(message([] { uv_sphere_mesh(1, 4096, 65536); }).find("vertices"), std::string::npos);
  EXPECT_NE(message([] { uv_sphere_mesh(1, 1, 8); }).find("rings"), std::string::npos);
  EXPECT_NE(message([] { rectangle_mesh(Vec2(1, 1), 0, 3); }).find("cell"), std::string::npos);
  EXPECT_NE(message([] { checkerboard(Vec2i(8, 8), 0, Color{}, Color{}); }).find("cells"), std::string::npos);
}

}  // namespace
}  // namespace loom::generate
