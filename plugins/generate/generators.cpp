#include "generators.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "loom/error.hpp"

namespace loom::generate {

namespace {

void every_64_rows(int row, const Check& check) {
  if (check && row % 64 == 0) check();
}

}  // namespace

Mesh grid_mesh(int nx, int ny, const Position& position, const std::function<bool(int, int)>& keep,
               const Check& check) {
  if (nx < 1 || ny < 1) throw Error("a grid needs at least one cell along x and y");
  Mesh mesh;
  mesh.V.resize((nx + 1) * (ny + 1), 3);
  mesh.UV.resize(mesh.V.rows(), 2);
  auto index = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j <= ny; ++j) {
    every_64_rows(j, check);
    for (int i = 0; i <= nx; ++i) {
      const double u = static_cast<double>(i) / nx, v = static_cast<double>(j) / ny;
      mesh.V.row(index(i, j)) = position(u, v);
      mesh.UV.row(index(i, j)) << u, v;
    }
  }
  int cells = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) cells += !keep || keep(i, j);
  mesh.F.resize(2 * cells, 3);
  int f = 0;
  for (int j = 0; j < ny; ++j) {
    every_64_rows(j, check);
    for (int i = 0; i < nx; ++i) {
      if (keep && !keep(i, j)) continue;
      mesh.F.row(f++) << index(i, j), index(i + 1, j), index(i + 1, j + 1);
      mesh.F.row(f++) << index(i, j), index(i + 1, j + 1), index(i, j + 1);
    }
  }
  return mesh;
}

void require_polar_counts(int rings, int segments) {
  if (rings < 1) throw Error("rings must be at least 1");
  if (segments < 3) throw Error("segments must be at least 3");
  // Each declared range alone is reasonable; their product may not be (4096
  // rings of 65536 segments is 268M vertices, 6 GB of faces).
  constexpr long long kMaxVertices = 1LL << 24;
  const long long n = static_cast<long long>(rings) * segments;
  if (n > kMaxVertices)
    throw Error("rings × segments = " + std::to_string(n) + " vertices: more than the " +
                std::to_string(kMaxVertices) + " a generated mesh may have");
}

Mesh polar_mesh(int rings, int segments, const Position& position, const Check& check) {
  require_polar_counts(rings, segments);
  Mesh mesh;
  mesh.V.resize(1 + rings * segments, 3);
  mesh.F.resize(segments * (2 * rings - 1), 3);
  mesh.V.row(0) = position(0.0, 0.0);
  auto index = [&](int ring, int s) { return 1 + (ring - 1) * segments + (s % segments); };
  for (int r = 1; r <= rings; ++r) {
    every_64_rows(r, check);
    for (int s = 0; s < segments; ++s)
      mesh.V.row(index(r, s)) = position(static_cast<double>(r) / rings, 2 * M_PI * s / segments);
  }
  int f = 0;
  for (int s = 0; s < segments; ++s) mesh.F.row(f++) << 0, index(1, s), index(1, s + 1);
  for (int r = 1; r < rings; ++r) {
    every_64_rows(r, check);
    for (int s = 0; s < segments; ++s) {
      mesh.F.row(f++) << index(r, s), index(r + 1, s), index(r + 1, s + 1);
      mesh.F.row(f++) << index(r, s), index(r + 1, s + 1), index(r, s + 1);
    }
  }
  return mesh;
}

Mesh rectangle_mesh(const Vec2& size, int nx, int ny, const Check& check) {
  return grid_mesh(
      nx, ny, [&](double u, double v) { return Eigen::Vector3d((u - 0.5) * size.x(), (v - 0.5) * size.y(), 0); }, {},
      check);
}

Mesh disk_mesh(double R, int rings, int segments, double h, const Check& check) {
  return polar_mesh(
      rings, segments,
      [&](double t, double phi) {
        const double x = R * t * std::cos(phi), y = R * t * std::sin(phi);
        const double z = h * std::sin(2 * M_PI * x / R) * std::sin(2 * M_PI * y / R) * (1 - t * t);
        return Eigen::Vector3d(x, y, z);
      },
      check);
}

Mesh hemisphere_mesh(double R, int rings, int segments, double noise, std::mt19937_64& rng, const Check& check) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return polar_mesh(
      rings, segments,
      [&](double t, double phi) {
        const double theta = t * M_PI / 2;  // polar angle from the pole
        const double r = R * (1 + noise * u(rng));
        return Eigen::Vector3d(r * std::sin(theta) * std::cos(phi), r * std::sin(theta) * std::sin(phi),
                               r * std::cos(theta));
      },
      check);
}

Mesh uv_sphere_mesh(double R, int rings, int segs, const Check& check) {
  if (rings < 2) throw Error("rings must be at least 2: a sphere needs one latitude ring between its poles");
  require_polar_counts(rings, segs);
  Mesh mesh;
  const int n = 2 + (rings - 1) * segs;
  mesh.V.resize(n, 3);
  mesh.N.resize(n, 3);
  mesh.V.row(0) << 0, 0, R;
  mesh.V.row(n - 1) << 0, 0, -R;
  auto index = [&](int ring, int s) { return 1 + (ring - 1) * segs + (s % segs); };
  for (int r = 1; r < rings; ++r) {
    every_64_rows(r, check);
    for (int s = 0; s < segs; ++s) {
      const double theta = M_PI * r / rings, phi = 2 * M_PI * s / segs;
      mesh.V.row(index(r, s)) << R * std::sin(theta) * std::cos(phi), R * std::sin(theta) * std::sin(phi),
          R * std::cos(theta);
    }
  }
  mesh.F.resize(2 * segs * (rings - 1), 3);
  int f = 0;
  for (int s = 0; s < segs; ++s) {
    mesh.F.row(f++) << 0, index(1, s), index(1, s + 1);
    mesh.F.row(f++) << n - 1, index(rings - 1, s + 1), index(rings - 1, s);
  }
  for (int r = 1; r < rings - 1; ++r) {
    every_64_rows(r, check);
    for (int s = 0; s < segs; ++s) {
      mesh.F.row(f++) << index(r, s), index(r + 1, s), index(r + 1, s + 1);
      mesh.F.row(f++) << index(r, s), index(r + 1, s + 1), index(r, s + 1);
    }
  }
  mesh.N = mesh.V / R;
  return mesh;
}

cv::Mat checkerboard(const Vec2i& size, int cells, const Color& color_a, const Color& color_b, const Check& check) {
  if (size.x() < 1 || size.y() < 1) throw Error("size must be at least 1 by 1 pixel");
  if (cells < 1) throw Error("cells must be at least 1");
  const auto& a = color_a.rgba;
  const auto& b = color_b.rgba;
  const double cell = static_cast<double>(std::min(size.x(), size.y())) / cells;
  cv::Mat m(size.y(), size.x(), CV_32FC3);
  for (int y = 0; y < m.rows; ++y) {
    every_64_rows(y, check);
    auto* row = m.ptr<cv::Vec3f>(y);
    const int cy = static_cast<int>(y / cell);
    for (int x = 0; x < m.cols; ++x) {
      const auto& c = ((static_cast<int>(x / cell) + cy) % 2 == 0) ? a : b;
      row[x] = cv::Vec3f(static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2]));
    }
  }
  return m;
}

}  // namespace loom::generate
