#include <cmath>

#include <Eigen/SparseCore>

#include "implicit_solvers.hpp"
#include "incremental_potential.hpp"
#include "loom/numerics/sparse_assembly.hpp"

namespace loom::cloth {
namespace {

// Unknown row (3 per free vertex) of each vertex, −1 if fixed.
std::vector<int> dof_rows(const SpringSystem& s) {
  std::vector<int> row(s.vertices(), -1);
  int next = 0;
  for (int i = 0; i < s.vertices(); ++i)
    if (!s.fixed[i]) row[i] = 3 * next++;
  return row;
}

// M + h² Σ_s H_s over the free unknowns (both triangles).
loom::numerics::SparseMatrix hessian(const SpringSystem& s, const std::vector<int>& row, int dofs,
                                     const Eigen::MatrixX3d& x, double h, const SolveOptions& options) {
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<size_t>(dofs) + 36 * static_cast<size_t>(s.spring_count()));
  for (int i = 0; i < s.vertices(); ++i)
    if (row[i] >= 0)
      for (int c = 0; c < 3; ++c) t.emplace_back(row[i] + c, row[i] + c, s.mass[i]);
  for (Eigen::Index k = 0; k < s.springs.rows(); ++k) {
    if (options.check && k % 32768 == 0) options.check();
    const int a = s.springs(k, 0), b = s.springs(k, 1);
    if (row[a] < 0 && row[b] < 0) continue;
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
      for (int q = 0; q < 2; ++q) {
        const int rp = row[s.springs(k, p)], rq = row[s.springs(k, q)];
        if (rp < 0 || rq < 0) continue;
        const double sign = p == q ? 1 : -1;
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) t.emplace_back(rp + i, rq + j, sign * block(i, j));
      }
  }
  if (options.penalty) {
    std::vector<std::pair<int, Eigen::Matrix3d>> blocks;
    options.penalty(x, nullptr, &blocks);
    for (const auto& [v, block] : blocks)
      if (row[v] >= 0)
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) t.emplace_back(row[v] + i, row[v] + j, h * h * block(i, j));
  }
  return loom::numerics::sparse_from_triplets(dofs, dofs, t, options.check);
}

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

Eigen::MatrixX3d newton_solve(const SpringSystem& s, const Eigen::MatrixX3d& y, double h,
                              Eigen::MatrixX3d x, const SolveOptions& options, SolveReport* report,
                              loom::numerics::SparseCholesky* factor) {
  const std::vector<int> row = dof_rows(s);
  const int dofs = 3 * (s.vertices() - s.fixed_count());
  SolveReport local;
  SolveReport& rep = report ? *report : local;
  rep = {};
  if (dofs == 0) {
    rep.converged = true;
    return x;
  }
  loom::numerics::SparseCholesky fresh;
  loom::numerics::SparseCholesky& cholesky = factor ? *factor : fresh;
  double energy = potential(s, x, y, h, options);
  Eigen::VectorXd g = gather(gradient(s, x, y, h, options), row, dofs);
  const double g0 = g.norm();
  if (g0 == 0) {
    rep.converged = true;
    return x;
  }
  for (int it = 0; it < options.iterations; ++it) {
    cholesky.refactor(hessian(s, row, dofs, x, h, options), options.check);
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
