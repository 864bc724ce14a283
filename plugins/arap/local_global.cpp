#include "local_global.hpp"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "loom/numerics/anderson.hpp"
#include "loom/numerics/sparse_assembly.hpp"
#include "loom/numerics/svd.hpp"

namespace loom::arap {

namespace {

// The hybrid model's L_t = r (P, Q)/|(P, Q)|: r >= 0 minimizes
// C r² − 2 r s + λ (r² − 1)², i.e. solves 2λ r³ + (C − 2λ) r − s = 0 (Liu et
// al. §5.2). g(r) = r (2λ (r² − 1) + C) − s is convex for r > 0 with one
// positive root; Newton from r0 = max(1, s/C), where g >= 0, descends to it.
double hybrid_scale(double C, double s, double lambda) {
  if (C <= 0) return 1;
  double r = std::max(1.0, s / C);
  for (int k = 0; k < 60; ++k) {
    const double g = r * (2 * lambda * (r * r - 1) + C) - s;
    const double dg = 6 * lambda * r * r + C - 2 * lambda;
    if (dg <= 0) break;
    const double step = g / dg;
    r -= step;
    if (std::abs(step) <= 1e-15 * r) break;
  }
  return std::max(r, 0.0);
}

// Local step on triangle t: the best L_t = [a −b; b a] for the current u,
// returned as (a, b), and the triangle's energy (without the ½).
Eigen::Vector2d local_fit(const TriangleFrames& fr, const Eigen::MatrixX3i& F,
                          const Eigen::MatrixX2d& UV, Eigen::Index t, double lambda,
                          double* energy) {
  Eigen::Vector2d e[3], d[3];
  Eigen::Matrix2d S = Eigen::Matrix2d::Zero();
  double C = 0;
  for (int i = 0; i < 3; ++i) {
    e[i] = (UV.row(F(t, i)) - UV.row(F(t, (i + 1) % 3))).transpose();
    d[i] = {fr.D(t, 2 * i), fr.D(t, 2 * i + 1)};
    S += fr.cot(t, i) * e[i] * d[i].transpose();  // S_t(u) = Σ c e d^T
    C += fr.cot(t, i) * d[i].squaredNorm();
  }
  Eigen::Vector2d ab;
  double extra = 0;
  if (lambda < 0) {
    const Eigen::Matrix2d R = numerics::closest_rotation_2x2(S);  // U V^T, det = +1
    ab = {R(0, 0), R(1, 0)};
  } else {
    const double P = S(0, 0) + S(1, 1), Q = S(1, 0) - S(0, 1), s = std::hypot(P, Q);
    const double r = hybrid_scale(C, s, lambda);
    ab = s > 0 ? Eigen::Vector2d(r * P / s, r * Q / s) : Eigen::Vector2d(r, 0);
    extra = lambda * (r * r - 1) * (r * r - 1);
  }
  Eigen::Matrix2d L;
  L << ab[0], -ab[1], ab[1], ab[0];
  double E = extra;
  for (int i = 0; i < 3; ++i) E += fr.cot(t, i) * (e[i] - L * d[i]).squaredNorm();
  *energy = E;
  return ab;
}

// b(L) of the global step, in parallel: each corner's share (3t + i), then
// per free vertex the sum over its corners plus the pinned vertices' share.
void gather_rhs(const ArapSystem& sys, const Eigen::MatrixX2d& ab, const Eigen::MatrixX2d& pinned_rhs,
                Eigen::MatrixXd& corner_rhs, Eigen::MatrixXd& rhs) {
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, sys.F.rows(), 1024), [&](const auto& range) {
    for (Eigen::Index t = range.begin(); t < range.end(); ++t) {
      Eigen::Matrix2d L;
      L << ab(t, 0), -ab(t, 1), ab(t, 1), ab(t, 0);
      Eigen::Vector2d r[3];
      for (int i = 0; i < 3; ++i)
        r[i] = sys.frames.cot(t, i) * (L * Eigen::Vector2d(sys.frames.D(t, 2 * i), sys.frames.D(t, 2 * i + 1)));
      for (int i = 0; i < 3; ++i) corner_rhs.row(3 * t + i) = (r[i] - r[(i + 2) % 3]).transpose();
    }
  });
  tbb::parallel_for(tbb::blocked_range<int>(0, static_cast<int>(rhs.rows()), 2048), [&](const auto& range) {
    for (int k = range.begin(); k < range.end(); ++k) {
      Eigen::RowVector2d b = pinned_rhs.row(k);
      for (int c = sys.corner_start[k]; c < sys.corner_start[k + 1]; ++c) b += corner_rhs.row(sys.corners[c]);
      rhs.row(k) = b;
    }
  });
}

}  // namespace

ArapSystem arap_system(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                       std::vector<int> pinned, const std::function<void()>& check) {
  const auto check_now = [&] {
    if (check) check();
  };
  const int n = static_cast<int>(V.rows());
  ArapSystem sys;
  sys.frames = triangle_frames(V, F);
  sys.F = F;
  check_now();
  const MeshParts parts = mesh_parts(F, n);
  std::vector<bool> part_pinned(parts.count, false), held(n, false);
  for (int v : pinned)
    if (parts.part[v] >= 0) part_pinned[parts.part[v]] = true;
  for (int k = 0; k < parts.count; ++k)
    if (!part_pinned[k]) pinned.push_back(parts.first_vertex[k]);
  for (int v : pinned) held[v] = true;

  sys.free_index.assign(n, -1);
  for (int v = 0; v < n; ++v)
    if (parts.part[v] >= 0 && !held[v]) {
      sys.free_index[v] = static_cast<int>(sys.free_vertex.size());
      sys.free_vertex.push_back(v);
    }
  const int nfree = static_cast<int>(sys.free_vertex.size());

  sys.corner_start.assign(nfree + 1, 0);
  for (Eigen::Index t = 0; t < F.rows(); ++t)
    for (int i = 0; i < 3; ++i)
      if (sys.free_index[F(t, i)] >= 0) ++sys.corner_start[sys.free_index[F(t, i)] + 1];
  for (int k = 0; k < nfree; ++k) sys.corner_start[k + 1] += sys.corner_start[k];
  sys.corners.resize(sys.corner_start[nfree]);
  std::vector<int> fill(sys.corner_start.begin(), sys.corner_start.end() - 1);
  for (Eigen::Index t = 0; t < F.rows(); ++t)
    for (int i = 0; i < 3; ++i)
      if (sys.free_index[F(t, i)] >= 0)
        sys.corners[fill[sys.free_index[F(t, i)]]++] = static_cast<int>(3 * t + i);

  check_now();
  std::vector<Eigen::Triplet<double>> ff, fp;
  ff.reserve(F.rows() * 9);
  for (Eigen::Index t = 0; t < F.rows(); ++t) {
    if (t % 65536 == 0) check_now();
    for (int i = 0; i < 3; ++i) {
      const int a = F(t, i), b = F(t, (i + 1) % 3);
      const double c = sys.frames.cot(t, i);
      const int fa = sys.free_index[a], fb = sys.free_index[b];
      if (fa >= 0) ff.emplace_back(fa, fa, c);
      if (fb >= 0) ff.emplace_back(fb, fb, c);
      if (fa >= 0 && fb >= 0) ff.emplace_back(fa, fb, -c), ff.emplace_back(fb, fa, -c);
      if (fa >= 0 && fb < 0) fp.emplace_back(fa, b, -c);
      if (fb >= 0 && fa < 0) fp.emplace_back(fb, a, -c);
    }
  }
  sys.K = numerics::sparse_from_triplets(nfree, nfree, ff, check);
  sys.K_fp = numerics::sparse_from_triplets(nfree, n, fp, check);
  check_now();
  if (nfree > 0) sys.K_ff.compute(sys.K, check);
  return sys;
}

ArapResult arap(const ArapSystem& sys, const Eigen::MatrixX2d& UV0, const ArapOptions& options,
                const std::function<void(int, double, const Eigen::MatrixX2d&)>& after_iteration) {
  const Eigen::MatrixX3i& F = sys.F;
  const Eigen::Index nf = F.rows();
  const int nfree = static_cast<int>(sys.free_vertex.size());
  ArapResult out;
  out.UV = UV0;
  Eigen::MatrixX2d ab(nf, 2);
  Eigen::VectorXd face_energy(nf);

  // Local step, in parallel over triangles; the sum is serial so that the
  // energy does not depend on the thread count.
  auto local_step = [&] {
    tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, nf, 1024), [&](const auto& range) {
      for (Eigen::Index t = range.begin(); t < range.end(); ++t) {
        double E;
        ab.row(t) = local_fit(sys.frames, F, out.UV, t, options.lambda, &E).transpose();
        face_energy[t] = E;
      }
    });
    return 0.5 * face_energy.sum();
  };

  // −K_fp u_p: the pinned vertices' share of the right-hand side, constant.
  const Eigen::MatrixX2d pinned_rhs = -(sys.K_fp * UV0);
  Eigen::MatrixXd corner_rhs(3 * nf, 2), rhs(nfree, 2);

  // Global step: b(L) gathered per free vertex from its corners, then one
  // back-substitution with the factor of K_ff. Returns the free vertices'
  // new UVs (#free by 2) for the rotations in `ab`.
  auto global_step = [&] {
    gather_rhs(sys, ab, pinned_rhs, corner_rhs, rhs);
    return Eigen::MatrixXd(sys.K_ff.solve(rhs));
  };
  auto free_rows = [&] {
    Eigen::MatrixXd x(nfree, 2);
    for (int k = 0; k < nfree; ++k) x.row(k) = out.UV.row(sys.free_vertex[k]);
    return x;
  };
  auto set_free_rows = [&](const Eigen::MatrixXd& x) {
    for (int k = 0; k < nfree; ++k) out.UV.row(sys.free_vertex[k]) = x.row(k);
  };

  double E = local_step();
  out.energy.push_back(E);
  if (nfree == 0 || E <= 0) {
    out.converged = true;
    return out;
  }
  // u: the accepted iterate (free rows), whose rotations are in `ab`.
  numerics::AndersonMixing mixing(options.anderson, 2 * static_cast<Eigen::Index>(nfree));
  Eigen::MatrixXd u = free_rows();
  for (int k = 1; k <= options.max_iterations; ++k) {
    const Eigen::MatrixXd g = global_step();  // G(u): one plain local/global iteration
    Eigen::MatrixXd next = mixing.extrapolate(u, g);
    set_free_rows(next);
    double E_next = local_step();
    if (!(E_next < E) && mixing.active()) {
      // Safeguard (Peng et al. 2018, §3.2): the extrapolation raised the
      // energy, so take the plain step, which never does, and start the
      // history again.
      mixing.reset();
      next = g;
      set_free_rows(next);
      E_next = local_step();
    }
    u = std::move(next);
    out.energy.push_back(E_next);
    out.iterations = k;
    if (after_iteration) after_iteration(k, E_next, out.UV);
    const bool done = E - E_next <= options.tolerance * E;
    E = E_next;
    if (done) {
      out.converged = true;
      break;
    }
  }
  return out;
}

double local_global_energy(const TriangleFrames& frames, const Eigen::MatrixX3i& F, const Eigen::MatrixX2d& UV,
                           double lambda) {
  double E = 0;
  for (Eigen::Index t = 0; t < F.rows(); ++t) {
    double Et;
    local_fit(frames, F, UV, t, lambda, &Et);
    E += Et;
  }
  return 0.5 * E;
}

}  // namespace loom::arap
