#include "loom/numerics/laplacian.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "loom/error.hpp"
#include "loom/numerics/sparse_assembly.hpp"

namespace loom::numerics {

namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

SparseMatrix from_triplets(const Triplets& t, int n, const std::function<void()>& check = {}) {
  return sparse_from_triplets(n, n, t, check);
}

void check_every(int f, const std::function<void()>& check) {
  if (check && f % 65536 == 0) check();
}

// A triangle is degenerate when its doubled area is negligible against its
// squared edge lengths: its angles (and so its weights) are then meaningless.
bool degenerate(double doubled_area, double squared_lengths) {
  return !(doubled_area > 1e-12 * squared_lengths);
}

}  // namespace

SparseMatrix uniform_weights(const Eigen::MatrixX3i& F, int n) {
  Triplets t;
  t.reserve(6 * static_cast<size_t>(F.rows()));
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      t.emplace_back(a, b, 1.0);
      t.emplace_back(b, a, 1.0);
    }
  SparseMatrix W(n, n);
  W.setFromTriplets(t.begin(), t.end(), [](double a, double) { return a; });
  return W;
}

// cot of the angle at corner k = (e1·e2) / |e1×e2| with e1, e2 the two edges
// leaving it; each face adds half of it to the opposite edge (i, j).
SparseMatrix cotangent_weights(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                               const std::function<void()>& check) {
  Triplets t;
  t.reserve(6 * static_cast<size_t>(F.rows()));
  for (int f = 0; f < F.rows(); ++f) {
    check_every(f, check);
    const Eigen::Vector3d u = V.row(F(f, 1)) - V.row(F(f, 0));
    const Eigen::Vector3d v = V.row(F(f, 2)) - V.row(F(f, 0));
    const double cross = u.cross(v).norm();
    if (degenerate(cross, u.squaredNorm() + v.squaredNorm())) continue;
    for (int k = 0; k < 3; ++k) {
      const int c = F(f, k), i = F(f, (k + 1) % 3), j = F(f, (k + 2) % 3);
      const Eigen::Vector3d e1 = V.row(i) - V.row(c), e2 = V.row(j) - V.row(c);
      const double w = 0.5 * e1.dot(e2) / cross;
      t.emplace_back(i, j, w);
      t.emplace_back(j, i, w);
    }
  }
  return from_triplets(t, static_cast<int>(V.rows()), check);
}

// tan(θ/2) = |a×b| / (|a||b| + a·b) for the angle θ between a and b; a face
// with corner i and edges a = x_j - x_i, b = x_k - x_i adds tan(θ_i/2)/|a| to
// w_ij and tan(θ_i/2)/|b| to w_ik (Floater 2003, eq. 5.1).
SparseMatrix mean_value_weights(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                const std::function<void()>& check) {
  Triplets t;
  t.reserve(6 * static_cast<size_t>(F.rows()));
  for (int f = 0; f < F.rows(); ++f) {
    check_every(f, check);
    const Eigen::Vector3d e1 = V.row(F(f, 1)) - V.row(F(f, 0));
    const Eigen::Vector3d e2 = V.row(F(f, 2)) - V.row(F(f, 0));
    if (degenerate(e1.cross(e2).norm(), e1.squaredNorm() + e2.squaredNorm())) continue;
    for (int k = 0; k < 3; ++k) {
      const int i = F(f, k), j = F(f, (k + 1) % 3), l = F(f, (k + 2) % 3);
      const Eigen::Vector3d a = V.row(j) - V.row(i), b = V.row(l) - V.row(i);
      const double la = a.norm(), lb = b.norm();
      const double half_tan = a.cross(b).norm() / (la * lb + a.dot(b));
      t.emplace_back(i, j, half_tan / la);
      t.emplace_back(i, l, half_tan / lb);
    }
  }
  return from_triplets(t, static_cast<int>(V.rows()), check);
}

namespace {

// An intrinsic triangulation: the faces of F as triples of half-edge slots
// 3f, 3f+1, 3f+2 (slot s runs from tail[s] to the tail of the next slot of
// its face), twin[s] the opposite slot or -1 on the boundary, edge[s] the
// undirected edge whose length is length[edge[s]]. Flips rewrite two faces in
// place (Sharp, Soliman and Crane 2019, "Navigating intrinsic
// triangulations", section 3.1), so edges may come to join vertices that are
// not mesh neighbours and two vertices may be joined by several edges.
struct IntrinsicTriangulation {
  std::vector<int> tail, twin, edge;
  std::vector<double> length;
  std::vector<int> slot_of_edge;  // one slot of each edge

  static int next(int s) { return s - s % 3 + (s % 3 + 1) % 3; }
  static int prev(int s) { return s - s % 3 + (s % 3 + 2) % 3; }

  // cot of the angle opposite slot s in its face, from the three lengths:
  // cot = (b² + c² - a²) / (4 · area) with Heron's area (Kahan's stable form).
  // A flat face (collinear or coincident vertices) has no cotangents: as a
  // Delaunay test its angle opposite the longest edge counts as π (so that
  // edge gets flipped), as a weight it contributes nothing.
  double cot_opposite(int s) const {
    const double a = length[edge[s]], b = length[edge[next(s)]], c = length[edge[prev(s)]];
    const double num = b * b + c * c - a * a;
    if (flat(s)) return num >= 0 ? 0.0 : -1e12;
    return num / area4(s);
  }
  double area4(int s) const {  // 4 · area, Heron's formula in Kahan's stable form
    double x[3] = {length[edge[s]], length[edge[next(s)]], length[edge[prev(s)]]};
    std::sort(x, x + 3, [](double p, double q) { return p > q; });
    const double q = (x[0] + (x[1] + x[2])) * (x[2] - (x[0] - x[1])) *
                     (x[2] + (x[0] - x[1])) * (x[0] + (x[1] - x[2]));
    return std::sqrt(std::max(q, 0.0));
  }
  bool flat(int s) const {
    const double b = length[edge[next(s)]], c = length[edge[prev(s)]], a = length[edge[s]];
    return degenerate(area4(s), a * a + b * b + c * c);
  }

  // Locally Delaunay: the angles opposite the edge sum to at most π, i.e.
  // cot α + cot β >= 0 (Bobenko and Springborn 2007, section 2).
  bool delaunay(int s) const {
    if (twin[s] < 0) return true;
    return cot_opposite(s) + cot_opposite(twin[s]) >= -1e-12;
  }

  // Flips the edge of slot h (i→j, face i j k) whose twin t (j→i, face j i l)
  // into the edge k-l; faces become (k l j) and (l k i). Returns false when
  // the two faces share another edge, where a flip is not defined.
  bool flip(int h) {
    const int t = twin[h];
    const int h1 = next(h), h2 = prev(h), t1 = next(t), t2 = prev(t);
    for (int s : {h1, h2})
      if (twin[s] == t || twin[s] == t1 || twin[s] == t2) return false;
    const int i = tail[h], j = tail[t], k = tail[h2], l = tail[t2];
    if (k == l) return false;
    // Lay the quad out in the plane: i at the origin, j on the x axis, k
    // above (face i j k is counter-clockwise), l below.
    const double lij = length[edge[h]];
    if (!(lij > 0)) return false;
    const double ljk = length[edge[h1]], lki = length[edge[h2]];
    const double lil = length[edge[t1]], llj = length[edge[t2]];
    const double kx = (lki * lki + lij * lij - ljk * ljk) / (2 * lij);
    const double ky = std::sqrt(std::max(lki * lki - kx * kx, 0.0));
    const double lx = (lil * lil + lij * lij - llj * llj) / (2 * lij);
    const double ly = -std::sqrt(std::max(lil * lil - lx * lx, 0.0));
    const double lkl = std::hypot(kx - lx, ky - ly);

    // Old half-edges that move: j→k (h1), k→i (h2), i→l (t1), l→j (t2).
    struct Moved { int twin, edge; };
    const Moved jk{twin[h1], edge[h1]}, ki{twin[h2], edge[h2]};
    const Moved il{twin[t1], edge[t1]}, lj{twin[t2], edge[t2]};
    auto place = [&](int slot, int from, const Moved& m) {
      tail[slot] = from;
      twin[slot] = m.twin;
      edge[slot] = m.edge;
      if (m.twin >= 0) twin[m.twin] = slot;
      slot_of_edge[m.edge] = slot;
    };
    // Face (k l j): h = k→l, h1 = l→j, h2 = j→k.
    tail[h] = k;
    place(h1, l, lj);
    place(h2, j, jk);
    // Face (l k i): t = l→k, t1 = k→i, t2 = i→l.
    tail[t] = l;
    place(t1, k, ki);
    place(t2, i, il);
    length[edge[h]] = lkl;
    return true;
  }
};

}  // namespace

SparseMatrix intrinsic_delaunay_cotangent_weights(const Eigen::MatrixX3d& V,
                                                  const Eigen::MatrixX3i& F) {
  const int m = static_cast<int>(F.rows());
  IntrinsicTriangulation T;
  T.tail.resize(3 * m);
  T.twin.assign(3 * m, -1);
  T.edge.resize(3 * m);
  std::vector<std::pair<std::uint64_t, int>> keys(3 * m);
  for (int f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      T.tail[3 * f + k] = a;
      keys[3 * f + k] = {(static_cast<std::uint64_t>(std::min(a, b)) << 32) |
                             static_cast<std::uint32_t>(std::max(a, b)),
                         3 * f + k};
    }
  std::sort(keys.begin(), keys.end());
  for (size_t i = 0; i < keys.size();) {
    size_t j = i;
    while (j < keys.size() && keys[j].first == keys[i].first) ++j;
    if (j - i > 2) {
      const auto a = keys[i].first >> 32, b = keys[i].first & 0xffffffffu;
      throw Error("non-manifold edge (" + std::to_string(a) + ", " + std::to_string(b) +
                  ") is used by " + std::to_string(j - i) + " faces; a surface edge may border at most two");
    }
    const int e = static_cast<int>(T.slot_of_edge.size());
    const int s = keys[i].second;
    T.slot_of_edge.push_back(s);
    T.length.push_back((V.row(F(s / 3, s % 3)) - V.row(F(s / 3, (s % 3 + 1) % 3))).norm());
    T.edge[s] = e;
    if (j - i == 2) {
      const int u = keys[i + 1].second;
      T.edge[u] = e;
      T.twin[s] = u;
      T.twin[u] = s;
    }
    i = j;
  }

  // Flip until every edge is locally Delaunay. Bobenko and Springborn prove
  // this terminates; the cap only guards against round-off cycling.
  const int edges = static_cast<int>(T.length.size());
  std::deque<int> queue;
  std::vector<char> queued(edges, 1);
  for (int e = 0; e < edges; ++e) queue.push_back(e);
  long long budget = 100LL * edges + 1000;
  while (!queue.empty() && budget-- > 0) {
    const int e = queue.front();
    queue.pop_front();
    queued[e] = 0;
    const int s = T.slot_of_edge[e];
    if (T.delaunay(s)) continue;
    const int t = T.twin[s];
    if (!T.flip(s)) continue;
    for (int r : {T.next(s), T.prev(s), T.next(t), T.prev(t)})
      if (!queued[T.edge[r]]) {
        queued[T.edge[r]] = 1;
        queue.push_back(T.edge[r]);
      }
  }

  Triplets trip;
  trip.reserve(6 * static_cast<size_t>(m));
  for (int s = 0; s < 3 * m; ++s) {
    if (T.flat(s)) continue;
    const double w = 0.5 * T.cot_opposite(s);
    const int a = T.tail[s], b = T.tail[T.next(s)];
    trip.emplace_back(a, b, w);
    trip.emplace_back(b, a, w);
  }
  return from_triplets(trip, static_cast<int>(V.rows()));
}

}  // namespace loom::numerics
