#include <cmath>
#include <vector>

#include <Eigen/Geometry>

#include "weights.hpp"

namespace loom::parameterize {

namespace {

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

}  // namespace

Eigen::SparseMatrix<double> shape_preserving_weights(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) {
  const int n = static_cast<int>(V.rows());
  // Around vertex a, face (a b c) leads from neighbour b to neighbour c (counter-clockwise).
  std::vector<std::vector<std::pair<int, int>>> ring(n);
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) ring[F(f, k)].emplace_back(F(f, (k + 1) % 3), F(f, (k + 2) % 3));

  std::vector<Eigen::Triplet<double>> t;
  std::vector<int> p;
  std::vector<Eigen::Vector2d> q;
  std::vector<double> mu;
  for (int v = 0; v < n; ++v) {
    const auto& pairs = ring[v];
    const int d = static_cast<int>(pairs.size());
    if (d < 3) continue;
    // Order the one-ring; a boundary vertex's ring does not close.
    p.assign(1, pairs[0].first);
    bool closed = true;
    for (int step = 0; step < d; ++step) {
      int next = -1;
      for (const auto& e : pairs)
        if (e.first == p.back()) next = e.second;
      if (next < 0) {
        closed = false;
        break;
      }
      if (next == p.front()) break;
      p.push_back(next);
    }
    if (!closed || static_cast<int>(p.size()) != d) continue;

    // Geodesic polar map: lengths kept, angles scaled to sum to 2π.
    std::vector<double> phi(d + 1, 0.0);
    for (int k = 0; k < d; ++k) {
      const Eigen::Vector3d a = V.row(p[k]) - V.row(v), b = V.row(p[(k + 1) % d]) - V.row(v);
      phi[k + 1] = phi[k] + std::atan2(a.cross(b).norm(), a.dot(b));
    }
    if (!(phi[d] > 0)) continue;
    q.resize(d);
    for (int k = 0; k < d; ++k) {
      const double angle = 2 * M_PI * phi[k] / phi[d], r = (V.row(p[k]) - V.row(v)).norm();
      q[k] = r * Eigen::Vector2d(std::cos(angle), std::sin(angle));
      phi[k] = angle;
    }
    phi[d] = 2 * M_PI;

    // For each neighbour l, the ring triangle (q_l, q_r, q_r+1) that the ray
    // from q_l through the vertex enters; barycentric coordinates of the
    // vertex there, averaged over l (Floater 1997, eq. 6.2).
    mu.assign(d, 0.0);
    int used = 0;
    for (int l = 0; l < d; ++l) {
      const double target = std::fmod(phi[l] + M_PI, 2 * M_PI);
      int r = 0;
      while (r + 1 < d && phi[r + 1] <= target) ++r;
      const int r1 = (r + 1) % d;
      if (r == l || r1 == l) continue;
      const Eigen::Vector2d &a = q[l], &b = q[r], &c = q[r1];
      const double area = cross2(b - a, c - a);
      if (!(area > 0)) continue;
      const double la = cross2(b, c) / area, lb = cross2(c, a) / area, lc = cross2(a, b) / area;
      if (la < -1e-12 || lb < -1e-12 || lc < -1e-12) continue;
      mu[l] += la;
      mu[r] += lb;
      mu[r1] += lc;
      ++used;
    }
    if (used == 0) continue;
    for (int k = 0; k < d; ++k)
      if (mu[k] != 0) t.emplace_back(v, p[k], mu[k] / used);
  }
  Eigen::SparseMatrix<double> W(n, n);
  W.setFromTriplets(t.begin(), t.end());
  return W;
}

}  // namespace loom::parameterize
