#include <algorithm>
#include <cmath>

#include <Eigen/SparseCore>

#include "implicit_solvers.hpp"
#include "incremental_potential.hpp"

namespace loom::cloth {

void NewtonWorkspace::prepare(const SpringSystem& s) {
  const auto same = [](const auto& a, const auto& b) { return a.rows() == b.rows() && a == b; };
  if (same(springs_, s.springs) && same(fixed_, s.fixed) && !row_.empty()) return;
  springs_ = s.springs;
  fixed_ = s.fixed;
  const int n = s.vertices();
  row_.assign(n, -1);
  int unknowns = 0;
  for (int i = 0; i < n; ++i)
    if (!s.fixed[i]) row_[i] = 3 * unknowns++;
  // Column block of each free vertex: the free vertices it shares a spring
  // with, and itself, in row order; each of its three columns holds their
  // three rows each.
  std::vector<std::vector<int>> coupled(n);
  for (int i = 0; i < n; ++i)
    if (row_[i] >= 0) coupled[i].push_back(i);
  for (Eigen::Index k = 0; k < s.springs.rows(); ++k) {
    const int a = s.springs(k, 0), b = s.springs(k, 1);
    if (row_[a] >= 0 && row_[b] >= 0 && a != b) coupled[a].push_back(b), coupled[b].push_back(a);
  }
  std::size_t entries = 0;
  for (auto& c : coupled) {
    std::sort(c.begin(), c.end());
    c.erase(std::unique(c.begin(), c.end()), c.end());
    entries += 9 * c.size();
  }
  matrix_ = loom::numerics::SparseMatrix(3 * unknowns, 3 * unknowns);
  matrix_.resizeNonZeros(static_cast<Eigen::Index>(entries));
  int* outer = matrix_.outerIndexPtr();
  int* inner = matrix_.innerIndexPtr();
  stride_.assign(n, 0);
  int at = 0;
  for (int v = 0; v < n; ++v) {
    if (row_[v] < 0) continue;
    stride_[v] = 3 * static_cast<int>(coupled[v].size());
    for (int j = 0; j < 3; ++j) {
      outer[row_[v] + j] = at;
      for (int u : coupled[v])
        for (int i = 0; i < 3; ++i) inner[at++] = row_[u] + i;
    }
  }
  outer[3 * unknowns] = at;
  // The entry (row of u, column of v), both free and coupled.
  auto block_at = [&](int u, int v) {
    const auto& c = coupled[v];
    return outer[row_[v]] + 3 * static_cast<int>(std::lower_bound(c.begin(), c.end(), u) - c.begin());
  };
  diagonal_at_.assign(n, -1);
  for (int v = 0; v < n; ++v)
    if (row_[v] >= 0) diagonal_at_[v] = block_at(v, v);
  spring_at_.assign(4 * static_cast<size_t>(s.spring_count()), -1);
  for (Eigen::Index k = 0; k < s.springs.rows(); ++k)
    for (int p = 0; p < 2; ++p)
      for (int q = 0; q < 2; ++q) {
        const int a = s.springs(k, p), b = s.springs(k, q);
        if (row_[a] >= 0 && row_[b] >= 0) spring_at_[4 * k + 2 * p + q] = block_at(a, b);
      }
}

void NewtonWorkspace::add_block(int at, int stride, const Eigen::Matrix3d& b, double scale) {
  double* value = matrix_.valuePtr() + at;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) value[j * stride + i] += scale * b(i, j);
}

// Each entry is the sum of its terms in the order a sum of triplets adds
// them: mass, springs in order (blocks (0,0), (0,1), (1,0), (1,1)), penalty.
// The values start at −0, which adds to any first term exactly.
const loom::numerics::SparseMatrix& NewtonWorkspace::hessian(const SpringSystem& s, const Eigen::MatrixX3d& x, double h,
                                                             const SolveOptions& options) {
  std::fill_n(matrix_.valuePtr(), matrix_.nonZeros(), -0.0);
  for (int i = 0; i < s.vertices(); ++i)
    if (row_[i] >= 0)
      for (int c = 0; c < 3; ++c) matrix_.valuePtr()[diagonal_at_[i] + c * stride_[i] + c] += s.mass[i];
  for (Eigen::Index k = 0; k < s.springs.rows(); ++k) {
    if (options.check && k % 32768 == 0) options.check();
    const int a = s.springs(k, 0), b = s.springs(k, 1);
    if (row_[a] < 0 && row_[b] < 0) continue;
    const Eigen::Vector3d r = (x.row(a) - x.row(b)).transpose();
    const double len = r.norm();
    Eigen::Matrix3d block;
    if (len > 0) {
      const Eigen::Vector3d u = r / len;
      const Eigen::Matrix3d uu = u * u.transpose();
      // Clamp of the l/‖r‖ − 1 term: compressed springs contribute only
      // along r̂, so the block stays positive semidefinite.
      block = uu + std::max(0.0, 1 - s.rest_length[k] / len) * (Eigen::Matrix3d::Identity() - uu);
    } else {
      block = Eigen::Matrix3d::Identity();  // coincident ends: any direction is r̂
    }
    block *= h * h * s.stiffness[k];
    for (int p = 0; p < 2; ++p)
      for (int q = 0; q < 2; ++q)
        if (const int at = spring_at_[4 * k + 2 * p + q]; at >= 0)
          add_block(at, stride_[s.springs(k, q)], block, p == q ? 1 : -1);
  }
  if (options.penalty) {
    std::vector<std::pair<int, Eigen::Matrix3d>> blocks;
    options.penalty(x, nullptr, &blocks);
    for (const auto& [v, block] : blocks)
      if (row_[v] >= 0) add_block(diagonal_at_[v], stride_[v], block, h * h);
  }
  return matrix_;
}

namespace {

Eigen::VectorXd gather(const Eigen::MatrixX3d& g, const std::vector<int>& row, int dofs) {
  Eigen::VectorXd out(dofs);
  for (size_t i = 0; i < row.size(); ++i)
    if (row[i] >= 0) out.segment<3>(row[i]) = g.row(static_cast<Eigen::Index>(i)).transpose();
  return out;
}

// E plus h² times the penalty, if any.
double potential(const SpringSystem& s, const Eigen::MatrixX3d& x, const Eigen::MatrixX3d& y, double h,
                 const SolveOptions& options) {
  const double e = incremental_potential(s, x, y, h);
  return options.penalty ? e + h * h * options.penalty(x, nullptr, nullptr) : e;
}

Eigen::MatrixX3d gradient(const SpringSystem& s, const Eigen::MatrixX3d& x, const Eigen::MatrixX3d& y, double h,
                          const SolveOptions& options) {
  Eigen::MatrixX3d g = incremental_gradient(s, x, y, h);
  if (options.penalty) {
    Eigen::MatrixX3d gp = Eigen::MatrixX3d::Zero(x.rows(), 3);
    options.penalty(x, &gp, nullptr);
    for (Eigen::Index i = 0; i < x.rows(); ++i)
      if (!s.fixed[i]) g.row(i) += h * h * gp.row(i);
  }
  return g;
}

}  // namespace

Eigen::MatrixX3d newton_solve(const SpringSystem& s, const Eigen::MatrixX3d& y, double h, Eigen::MatrixX3d x,
                              const SolveOptions& options, SolveReport* report, NewtonWorkspace* workspace) {
  NewtonWorkspace fresh;
  NewtonWorkspace& ws = workspace ? *workspace : fresh;
  ws.prepare(s);
  const std::vector<int>& row = ws.rows();
  const int dofs = ws.unknowns();
  SolveReport local;
  SolveReport& rep = report ? *report : local;
  rep = {};
  if (dofs == 0) {
    rep.converged = true;
    return x;
  }
  loom::numerics::SparseCholesky& cholesky = ws.factor();
  double energy = potential(s, x, y, h, options);
  Eigen::VectorXd g = gather(gradient(s, x, y, h, options), row, dofs);
  const double g0 = g.norm();
  rep.start_gradient = g0;
  if (g0 == 0) {
    rep.converged = true;
    return x;
  }
  for (int it = 0; it < options.iterations; ++it) {
    cholesky.refactor(ws.hessian(s, x, h, options), options.check);
    if (options.check) options.check();
    const Eigen::VectorXd p = -cholesky.solve(g);
    // Backtracking line search on E (Armijo, c = 1e-4): H is positive
    // definite, so p is a descent direction and a small enough step decreases E.
    const double slope = g.dot(p);
    double alpha = 1;
    Eigen::MatrixX3d trial = x;
    double trial_energy = energy;
    bool accepted = false;
    for (int halving = 0; halving < 40; ++halving, alpha *= 0.5) {
      if (options.check) options.check();
      trial = x;
      for (int i = 0; i < s.vertices(); ++i)
        if (row[i] >= 0) trial.row(i) += alpha * p.segment<3>(row[i]).transpose();
      trial_energy = potential(s, trial, y, h, options);
      if (std::isfinite(trial_energy) && trial_energy <= energy + 1e-4 * alpha * slope) {
        accepted = true;
        break;
      }
    }
    ++rep.iterations;
    if (options.after_iteration) options.after_iteration();
    // No decrease at all: x is a minimizer to rounding (the potential's
    // differences are below its roundoff).
    if (!accepted) {
      rep.residuals.push_back(g.norm() / g0);
      rep.converged = true;
      break;
    }
    const double step = alpha * p.norm();
    x = trial;
    if (options.project) options.project(x);
    energy = options.project ? potential(s, x, y, h, options) : trial_energy;
    g = gather(gradient(s, x, y, h, options), row, dofs);
    if (options.check) options.check();
    rep.residuals.push_back(g.norm() / g0);
    if (g.norm() <= options.tolerance * g0 || step <= 1e-16 * x.norm()) {
      rep.converged = true;
      break;
    }
  }
  return x;
}

}  // namespace loom::cloth
