#include "incremental_potential.hpp"

#include <cmath>

namespace loom::cloth {

double spring_energy(const SpringSystem& s, const Eigen::MatrixX3d& x) {
  double e = 0;
  for (Eigen::Index k = 0; k < s.springs.rows(); ++k) {
    const double stretch = (x.row(s.springs(k, 0)) - x.row(s.springs(k, 1))).norm() - s.rest_length[k];
    e += 0.5 * s.stiffness[k] * stretch * stretch;
  }
  return e;
}

Eigen::MatrixX3d spring_forces(const SpringSystem& s, const Eigen::MatrixX3d& x) {
  Eigen::MatrixX3d f = Eigen::MatrixX3d::Zero(x.rows(), 3);
  for (Eigen::Index k = 0; k < s.springs.rows(); ++k) {
    const int a = s.springs(k, 0), b = s.springs(k, 1);
    const Eigen::RowVector3d r = x.row(a) - x.row(b);
    const double len = r.norm();
    // At ‖r‖ = 0 the direction is undefined: the force is taken as zero there
    // (a subgradient of the energy), so coincident vertices stay finite.
    if (len == 0) continue;
    const Eigen::RowVector3d force = -s.stiffness[k] * (len - s.rest_length[k]) / len * r;
    f.row(a) += force;
    f.row(b) -= force;
  }
  return f;
}

double incremental_potential(const SpringSystem& s, const Eigen::MatrixX3d& x,
                             const Eigen::MatrixX3d& y, double h) {
  double inertia = 0;
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    if (!s.fixed[i]) inertia += s.mass[i] * (x.row(i) - y.row(i)).squaredNorm();
  return 0.5 * inertia + h * h * spring_energy(s, x);
}

Eigen::MatrixX3d incremental_gradient(const SpringSystem& s, const Eigen::MatrixX3d& x,
                                      const Eigen::MatrixX3d& y, double h) {
  Eigen::MatrixX3d g = -h * h * spring_forces(s, x);
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    if (s.fixed[i])
      g.row(i).setZero();
    else
      g.row(i) += s.mass[i] * (x.row(i) - y.row(i));
  }
  return g;
}

double total_energy(const SpringSystem& s, const Eigen::MatrixX3d& x, const Eigen::MatrixX3d& v,
                    const Eigen::Vector3d& gravity) {
  double e = spring_energy(s, x);
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    e += s.mass[i] * (0.5 * v.row(i).squaredNorm() - x.row(i).dot(gravity.transpose()));
  return e;
}

}  // namespace loom::cloth
