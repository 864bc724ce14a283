#include "mass_spring.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "loom/error.hpp"

namespace loom::cloth {
namespace {

// Appends springs from pairs, rest lengths measured on X.
void set_springs(SpringSystem& s, const std::vector<std::pair<int, int>>& pairs,
                 const std::vector<double>& k) {
  s.springs.resize(static_cast<Eigen::Index>(pairs.size()), 2);
  s.rest_length.resize(s.springs.rows());
  s.stiffness.resize(s.springs.rows());
  for (size_t e = 0; e < pairs.size(); ++e) {
    const auto r = static_cast<Eigen::Index>(e);
    s.springs.row(r) << pairs[e].first, pairs[e].second;
    s.rest_length[r] = (s.X.row(pairs[e].first) - s.X.row(pairs[e].second)).norm();
    s.stiffness[r] = k[e];
  }
}

}  // namespace

Eigen::VectorXd vertex_areas(const Eigen::MatrixX3d& x, const Eigen::MatrixX3i& F) {
  Eigen::VectorXd area = Eigen::VectorXd::Zero(x.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = x.row(F(f, 0)), b = x.row(F(f, 1)), c = x.row(F(f, 2));
    const double third = (b - a).cross(c - a).norm() / 6;
    for (int k = 0; k < 3; ++k) area[F(f, k)] += third;
  }
  return area;
}

SpringSystem mesh_springs(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                          double area_density, double k_edge, double k_bend) {
  SpringSystem s;
  s.X = V;
  s.F = F;
  // Each undirected edge with the vertices opposite it (one on a boundary).
  std::map<std::pair<int, int>, std::vector<int>> opposite;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3), c = F(f, (k + 2) % 3);
      opposite[{std::min(a, b), std::max(a, b)}].push_back(c);
    }
  std::vector<std::pair<int, int>> pairs;
  std::vector<double> k;
  for (const auto& [edge, opp] : opposite) {
    pairs.push_back(edge);
    k.push_back(k_edge);
  }
  if (k_bend > 0)
    for (const auto& [edge, opp] : opposite)
      if (opp.size() == 2 && opp[0] != opp[1]) {
        pairs.emplace_back(std::min(opp[0], opp[1]), std::max(opp[0], opp[1]));
        k.push_back(k_bend);
      }
  set_springs(s, pairs, k);
  s.mass = area_density * vertex_areas(V, F);
  const double mean = s.mass.size() > 0 ? s.mass.mean() : 0;
  for (Eigen::Index i = 0; i < s.mass.size(); ++i)
    if (s.mass[i] <= 0) s.mass[i] = mean > 0 ? mean : area_density;
  s.fixed = Eigen::VectorXi::Zero(V.rows());
  return s;
}

SpringSystem grid_cloth(int nx, int ny, const Eigen::Vector3d& origin, const Eigen::Vector3d& du,
                        const Eigen::Vector3d& dv, double area_density, double k_structural,
                        double k_shear, double k_bend) {
  if (nx < 2 || ny < 2) throw Error("a grid cloth needs at least 2 by 2 vertices");
  SpringSystem s;
  s.X.resize(nx * ny, 3);
  s.UV.resize(nx * ny, 2);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double u = static_cast<double>(i) / (nx - 1), v = static_cast<double>(j) / (ny - 1);
      s.X.row(grid_index(nx, i, j)) = (origin + du * u + dv * v).transpose();
      s.UV.row(grid_index(nx, i, j)) << u, v;
    }
  s.F.resize(2 * (nx - 1) * (ny - 1), 3);
  int f = 0;
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const int a = grid_index(nx, i, j), b = grid_index(nx, i + 1, j),
                c = grid_index(nx, i + 1, j + 1), d = grid_index(nx, i, j + 1);
      s.F.row(f++) << a, b, c;
      s.F.row(f++) << a, c, d;
    }
  std::vector<std::pair<int, int>> pairs;
  std::vector<double> k;
  auto add = [&](int i0, int j0, int i1, int j1, double stiffness) {
    if (stiffness <= 0 || i1 < 0 || i1 >= nx || j1 >= ny) return;
    pairs.emplace_back(grid_index(nx, i0, j0), grid_index(nx, i1, j1));
    k.push_back(stiffness);
  };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      add(i, j, i + 1, j, k_structural);
      add(i, j, i, j + 1, k_structural);
      add(i, j, i + 1, j + 1, k_shear);
      add(i, j, i - 1, j + 1, k_shear);
      add(i, j, i + 2, j, k_bend);
      add(i, j, i, j + 2, k_bend);
    }
  set_springs(s, pairs, k);
  s.mass = area_density * vertex_areas(s.X, s.F);
  s.fixed = Eigen::VectorXi::Zero(s.X.rows());
  return s;
}

SpringSystem cuboid_lattice(int nx, int ny, int nz, const Eigen::Vector3d& lo,
                            const Eigen::Vector3d& hi, double density, double k_edge, double k_face,
                            double k_body) {
  if (nx < 2 || ny < 2 || nz < 2) throw Error("a cuboid lattice needs at least 2 points per side");
  // About 13 springs a point: 4 million points already take gigabytes.
  if (double(nx) * ny * nz > 4'194'304)
    throw Error("a cuboid lattice of " + std::to_string(nx) + "×" + std::to_string(ny) + "×" + std::to_string(nz) +
                " points is more than the 4,194,304 (2^22) this node builds");
  const Eigen::Vector3i n(nx, ny, nz);
  auto index = [&](int i, int j, int k) { return (k * ny + j) * nx + i; };
  SpringSystem s;
  s.X.resize(nx * ny * nz, 3);
  const Eigen::Vector3d cell = (hi - lo).cwiseQuotient((n - Eigen::Vector3i::Ones()).cast<double>());
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        s.X.row(index(i, j, k)) = (lo + cell.cwiseProduct(Eigen::Vector3d(i, j, k))).transpose();
  // Every pair of corners of every cell, classified by how many axes differ;
  // a pair shared by two cells (an edge or face diagonal) is added once.
  std::map<std::pair<int, int>, double> unique;
  const double k_class[4] = {0, k_edge, k_face, k_body};
  for (int k = 0; k + 1 < nz; ++k)
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i)
        for (int a = 0; a < 8; ++a)
          for (int b = a + 1; b < 8; ++b) {
            const int differ = __builtin_popcount(a ^ b);
            if (k_class[differ] <= 0) continue;
            const int p = index(i + (a & 1), j + (a >> 1 & 1), k + (a >> 2 & 1));
            const int q = index(i + (b & 1), j + (b >> 1 & 1), k + (b >> 2 & 1));
            unique[{std::min(p, q), std::max(p, q)}] = k_class[differ];
          }
  std::vector<std::pair<int, int>> pairs;
  std::vector<double> ks;
  for (const auto& [pair, stiffness] : unique) {
    pairs.push_back(pair);
    ks.push_back(stiffness);
  }
  set_springs(s, pairs, ks);
  s.mass = Eigen::VectorXd::Zero(s.X.rows());
  const double share = density * cell.prod() / 8;
  for (int k = 0; k + 1 < nz; ++k)
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i)
        for (int a = 0; a < 8; ++a) s.mass[index(i + (a & 1), j + (a >> 1 & 1), k + (a >> 2 & 1))] += share;
  // The six faces, counter-clockwise seen from outside.
  std::vector<Eigen::Vector3i> tris;
  auto quad = [&](int a, int b, int c, int d) {
    tris.emplace_back(a, b, c);
    tris.emplace_back(a, c, d);
  };
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      quad(index(i, j, 0), index(i, j + 1, 0), index(i + 1, j + 1, 0), index(i + 1, j, 0));
      const int k = nz - 1;
      quad(index(i, j, k), index(i + 1, j, k), index(i + 1, j + 1, k), index(i, j + 1, k));
    }
  for (int k = 0; k + 1 < nz; ++k)
    for (int i = 0; i + 1 < nx; ++i) {
      quad(index(i, 0, k), index(i + 1, 0, k), index(i + 1, 0, k + 1), index(i, 0, k + 1));
      const int j = ny - 1;
      quad(index(i, j, k), index(i, j, k + 1), index(i + 1, j, k + 1), index(i + 1, j, k));
    }
  for (int k = 0; k + 1 < nz; ++k)
    for (int j = 0; j + 1 < ny; ++j) {
      quad(index(0, j, k), index(0, j, k + 1), index(0, j + 1, k + 1), index(0, j + 1, k));
      const int i = nx - 1;
      quad(index(i, j, k), index(i, j + 1, k), index(i, j + 1, k + 1), index(i, j, k + 1));
    }
  s.F.resize(static_cast<Eigen::Index>(tris.size()), 3);
  for (size_t t = 0; t < tris.size(); ++t) s.F.row(static_cast<Eigen::Index>(t)) = tris[t].transpose();
  s.fixed = Eigen::VectorXi::Zero(s.X.rows());
  return s;
}

void fix_vertices(SpringSystem& s, const std::vector<int>& indices, const Eigen::Vector3d& box_lo,
                  const Eigen::Vector3d& box_hi) {
  for (int i : indices) {
    if (i < 0 || i >= s.vertices())
      throw Error("fixed vertex " + std::to_string(i) + " is not a vertex (the system has " +
                  std::to_string(s.vertices()) + ")");
    s.fixed[i] = 1;
  }
  if ((box_lo.array() > box_hi.array()).any()) return;
  for (int i = 0; i < s.vertices(); ++i) {
    const Eigen::Vector3d p = s.X.row(i);
    if ((p.array() >= box_lo.array()).all() && (p.array() <= box_hi.array()).all()) s.fixed[i] = 1;
  }
}

void require_valid(const SpringSystem& s) {
  const int n = s.vertices();
  if (n == 0) throw Error("the mass-spring system has no vertices");
  if (!s.X.allFinite()) throw Error("the mass-spring system has NaN or infinite positions");
  if (s.mass.size() != n || s.fixed.size() != n)
    throw Error("the mass-spring system's masses or fixed flags do not match its vertices");
  const Eigen::Index m = s.springs.rows();
  if (s.rest_length.size() != m || s.stiffness.size() != m)
    throw Error("the mass-spring system's rest lengths or stiffnesses do not match its springs");
  for (Eigen::Index e = 0; e < m; ++e) {
    const int a = s.springs(e, 0), b = s.springs(e, 1);
    if (a < 0 || b < 0 || a >= n || b >= n)
      throw Error("spring " + std::to_string(e) + " joins a vertex that does not exist");
    if (a == b) throw Error("spring " + std::to_string(e) + " joins vertex " + std::to_string(a) + " to itself");
    if (!std::isfinite(s.stiffness[e]) || s.stiffness[e] < 0)
      throw Error("spring " + std::to_string(e) + " has a negative or non-finite stiffness");
    if (!std::isfinite(s.rest_length[e]) || s.rest_length[e] < 0)
      throw Error("spring " + std::to_string(e) + " has a negative or non-finite rest length");
  }
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(s.mass[i]) || s.mass[i] < 0)
      throw Error("vertex " + std::to_string(i) + " has a negative or non-finite mass");
    if (s.mass[i] == 0 && !s.fixed[i])
      throw Error("free vertex " + std::to_string(i) + " has zero mass: give the density a positive value");
  }
  for (Eigen::Index f = 0; f < s.F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (s.F(f, k) < 0 || s.F(f, k) >= n)
        throw Error("triangle " + std::to_string(f) + " names a vertex that does not exist");
  if ((s.UV.rows() != 0 && s.UV.rows() != n) || !s.UV.allFinite())
    throw Error("the mass-spring system's UVs do not match its vertices or are not finite");
  if ((s.C.rows() != 0 && s.C.rows() != n) || !s.C.allFinite())
    throw Error("the mass-spring system's colors do not match its vertices or are not finite");
}

}  // namespace loom::cloth
