#include "similarity_map.hpp"

#include <algorithm>
#include <array>
#include <string>

#include <Eigen/SparseCore>

#include "loom/error.hpp"
#include "loom/numerics/sparse_assembly.hpp"
#include "loom/numerics/sparse_solver.hpp"

namespace loom::arap {

namespace {

// The 6×6 quadratic form of one triangle's energy in (u0, v0, u1, v1, u2, v2)
// after eliminating its similarity (eq. 28 with (a_t, b_t) substituted).
Eigen::Matrix<double, 6, 6> triangle_form(const TriangleFrames& fr, Eigen::Index t) {
  Eigen::Matrix<double, 6, 6> M = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> p = Eigen::Matrix<double, 6, 1>::Zero(), q = p;
  double C = 0;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    const double c = fr.cot(t, i), dx = fr.D(t, 2 * i), dy = fr.D(t, 2 * i + 1);
    for (int k = 0; k < 2; ++k) {
      M(2 * i + k, 2 * i + k) += c;
      M(2 * j + k, 2 * j + k) += c;
      M(2 * i + k, 2 * j + k) -= c;
      M(2 * j + k, 2 * i + k) -= c;
    }
    // P = Σ c d·(u_i − u_j),  Q = Σ c d×(u_i − u_j)
    p(2 * i) += c * dx, p(2 * i + 1) += c * dy, p(2 * j) -= c * dx, p(2 * j + 1) -= c * dy;
    q(2 * i + 1) += c * dx, q(2 * i) -= c * dy, q(2 * j + 1) -= c * dx, q(2 * j) += c * dy;
    C += c * (dx * dx + dy * dy);
  }
  if (C > 0) M -= (p * p.transpose() + q * q.transpose()) / C;
  return M;
}

}  // namespace

SimilarityMap similarity_map(const TriangleFrames& frames, const Eigen::MatrixX3i& F, int n,
                             const std::vector<Pin>& pins, const std::function<void()>& check) {
  const auto check_every = [&](Eigen::Index t) {
    if (check && t % 32768 == 0) check();
  };
  SimilarityMap out;
  out.UV = Eigen::MatrixX2d::Zero(n, 2);
  std::vector<bool> referenced(n, false);
  for (Eigen::Index t = 0; t < F.rows(); ++t)
    for (int i = 0; i < 3; ++i) referenced[F(t, i)] = true;
  std::vector<int> free_index(n, -1);
  std::vector<bool> pinned(n, false);
  for (const Pin& p : pins) pinned[p.vertex] = true, out.UV.row(p.vertex) = p.uv.transpose();
  int nfree = 0;
  for (int v = 0; v < n; ++v)
    if (referenced[v] && !pinned[v]) free_index[v] = nfree++;

  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(F.rows() * 36);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(2 * nfree);
  for (Eigen::Index t = 0; t < F.rows(); ++t) {
    check_every(t);
    const Eigen::Matrix<double, 6, 6> M = triangle_form(frames, t);
    for (int a = 0; a < 6; ++a) {
      const int fa = free_index[F(t, a / 2)];
      if (fa < 0) continue;
      for (int b = 0; b < 6; ++b) {
        const int vb = F(t, b / 2), fb = free_index[vb];
        if (fb >= 0)
          triplets.emplace_back(2 * fa + a % 2, 2 * fb + b % 2, M(a, b));
        else
          rhs[2 * fa + a % 2] -= M(a, b) * out.UV(vb, b % 2);
      }
    }
  }
  if (nfree > 0) {
    numerics::SparseMatrix K = numerics::sparse_from_triplets(2 * nfree, 2 * nfree, triplets, check);
    triplets = {};
    numerics::SparseCholesky chol;
    try {
      chol.compute(K, check);
    } catch (const Cancelled&) {
      throw;
    } catch (const Error&) {
      // Parts joined at one vertex can turn about it freely: a shift much
      // smaller than the entries picks the solution nearest the origin.
      const double shift = 1e-8 * K.diagonal().cwiseAbs().mean();
      for (int k = 0; k < 2 * nfree; ++k) K.coeffRef(k, k) += shift;
      chol.compute(K, check);
      out.regularized = true;
    }
    const Eigen::VectorXd x = chol.solve(rhs);
    for (int v = 0; v < n; ++v)
      if (free_index[v] >= 0) out.UV.row(v) << x[2 * free_index[v]], x[2 * free_index[v] + 1];
  }
  double energy = 0;
  for (Eigen::Index t = 0; t < F.rows(); ++t) {
    check_every(t);
    Eigen::Matrix<double, 6, 1> u;
    for (int i = 0; i < 3; ++i) u.segment<2>(2 * i) = out.UV.row(F(t, i)).transpose();
    energy += 0.5 * u.dot(triangle_form(frames, t) * u);
  }
  out.energy = std::max(0.0, energy);
  return out;
}

std::vector<Pin> similarity_pins(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                 const std::vector<int>& given) {
  const int n = static_cast<int>(V.rows());
  const MeshParts parts = mesh_parts(F, n);
  std::vector<std::array<int, 2>> pairs = far_apart_pairs(V, parts);
  if (!given.empty()) {
    if (given.size() != 2)
      throw Error("pins needs two vertex indices (or none for automatic), got " +
                  std::to_string(given.size()));
    for (int v : given)
      if (v < 0 || v >= n || parts.part[v] < 0)
        throw Error("pin " + std::to_string(v) + " is not a vertex of a face (the mesh has " +
                    std::to_string(n) + " vertices)");
    if (given[0] == given[1] || parts.part[given[0]] != parts.part[given[1]])
      throw Error("pins " + std::to_string(given[0]) + " and " + std::to_string(given[1]) +
                  " must be two different vertices of one connected part");
    pairs[parts.part[given[0]]] = {given[0], given[1]};
  }
  std::vector<Pin> pins;
  double offset = 0;
  for (const auto& [a, b] : pairs) {
    const double d = (V.row(a) - V.row(b)).norm();
    pins.push_back({a, Eigen::Vector2d(offset, 0)});
    if (a != b) pins.push_back({b, Eigen::Vector2d(offset + d, 0)});
    offset += 1.2 * d;
  }
  return pins;
}

}  // namespace loom::arap
