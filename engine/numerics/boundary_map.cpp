#include "loom/numerics/boundary_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_set>

#include "loom/error.hpp"

namespace loom::numerics {

namespace {

// s[k] = arc length from loop[0] to loop[k]; s[#B] = total length L.
std::vector<double> arc_lengths(const Eigen::MatrixX3d& V, const std::vector<int>& loop) {
  std::vector<double> s(loop.size() + 1, 0.0);
  for (size_t k = 0; k < loop.size(); ++k)
    s[k + 1] = s[k] + (V.row(loop[(k + 1) % loop.size()]) - V.row(loop[k])).norm();
  return s;
}

// Corners from start position c: for q = 1..3 the position nearest to arc
// length q·L/4 past c, each after the previous one and leaving room for the
// ones still to place.
std::vector<int> corners_from(const std::vector<double>& s, int c) {
  const int n = static_cast<int>(s.size()) - 1;
  const double L = s[n];
  auto along = [&](int offset) {
    const double d = s[(c + offset) % n] - s[c];
    return d < 0 ? d + L : d;
  };
  std::vector<int> corners{c};
  int previous = 0;
  for (int q = 1; q < 4; ++q) {
    const double target = q * L / 4;
    int best = previous + 1;
    for (int o = previous + 2; o <= n - (4 - q); ++o) {
      if (std::abs(along(o) - target) >= std::abs(along(best) - target)) break;
      best = o;
    }
    corners.push_back((c + best) % n);
    previous = best;
  }
  return corners;
}

}  // namespace

std::vector<int> square_corners(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                const std::vector<int>& loop) {
  const int n = static_cast<int>(loop.size());
  if (n < 4) throw Error("the boundary has " + std::to_string(n) + " vertices: a square needs at least 4");
  const std::vector<double> s = arc_lengths(V, loop);
  // Ear tips: a face holding the boundary edges prev→tip and tip→next.
  std::unordered_set<std::uint64_t> boundary;
  auto key = [](int a, int b) { return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b); };
  for (int k = 0; k < n; ++k) boundary.insert(key(loop[k], loop[(k + 1) % n]));
  std::vector<int> position_of(V.rows(), -1);
  for (int k = 0; k < n; ++k) position_of[loop[k]] = k;
  std::vector<int> ears;
  for (int f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int a = F(f, c), b = F(f, (c + 1) % 3), d = F(f, (c + 2) % 3);
      if (boundary.count(key(a, b)) && boundary.count(key(b, d)) && position_of[b] >= 0)
        ears.push_back(position_of[b]);
    }
  std::sort(ears.begin(), ears.end());
  ears.erase(std::unique(ears.begin(), ears.end()), ears.end());
  if (ears.size() > 4) {
    // More ears than corners: the start that puts the most of them on corners.
    std::vector<int> best;
    int best_hits = -1;
    for (size_t e = 0; e < std::min<size_t>(ears.size(), 64); ++e) {
      std::vector<int> corners = corners_from(s, ears[e]);
      int hits = 0;
      for (int c : corners) hits += std::binary_search(ears.begin(), ears.end(), c);
      if (hits > best_hits) {
        best_hits = hits;
        best = corners;
      }
    }
    std::sort(best.begin(), best.end());
    return best;
  }
  // Every ear is a corner; the rest split the longest gaps at their arc-length middle.
  std::vector<int> corners = ears.empty() ? std::vector<int>{0} : ears;
  const double L = s[n];
  while (corners.size() < 4) {
    int best_vertex = -1;
    double best_length = -1;
    for (size_t g = 0; g < corners.size(); ++g) {
      const int a = corners[g], b = corners[(g + 1) % corners.size()];
      const int count = (b - a + n) % n == 0 ? n : (b - a + n) % n;  // edges in the gap
      if (count < 2) continue;
      const double length = corners.size() == 1 ? L : std::fmod(s[b] - s[a] + L, L);
      if (length <= best_length) continue;
      int vertex = (a + 1) % n;
      for (int o = 1; o < count; ++o) {
        const int k = (a + o) % n;
        if (std::abs(std::fmod(s[k] - s[a] + L, L) - length / 2) <
            std::abs(std::fmod(s[vertex] - s[a] + L, L) - length / 2))
          vertex = k;
      }
      best_vertex = vertex;
      best_length = length;
    }
    corners.push_back(best_vertex);
    std::sort(corners.begin(), corners.end());
  }
  return corners;
}

Eigen::MatrixX2d map_boundary(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                              const std::vector<int>& loop, BoundaryShape shape) {
  const int n = static_cast<int>(loop.size());
  if (n < 3) throw Error("the boundary has " + std::to_string(n) + " vertices: at least 3 are needed");
  const std::vector<double> s = arc_lengths(V, loop);
  if (!(s[n] > 0)) throw Error("the boundary has zero length: its vertices coincide");
  Eigen::MatrixX2d B(n, 2);
  if (shape == BoundaryShape::circle) {
    for (int k = 0; k < n; ++k) {
      const double t = 2 * M_PI * s[k] / s[n];
      B.row(k) << 0.5 + 0.5 * std::cos(t), 0.5 + 0.5 * std::sin(t);
    }
    return B;
  }
  const std::vector<int> corners = square_corners(V, F, loop);
  const Eigen::RowVector2d square[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int q = 0; q < 4; ++q) {
    const int a = corners[q], b = corners[(q + 1) % 4];
    const double sa = s[a], length = (b > a ? s[b] : s[n] + s[b]) - sa;
    for (int k = a;; k = (k + 1) % n) {
      if (k == b) break;
      const double along = (k >= a ? s[k] : s[n] + s[k]) - sa;
      const double t = length > 0 ? along / length : 0.0;
      B.row(k) = (1 - t) * square[q] + t * square[(q + 1) % 4];
    }
  }
  return B;
}

}  // namespace loom::numerics
