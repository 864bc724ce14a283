#include "loom/numerics/tangent_frames.hpp"

#include <cmath>

#include <Eigen/Geometry>

namespace loom::numerics {

Eigen::MatrixX3d vertex_normals(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) {
  Eigen::MatrixX3d N = Eigen::MatrixX3d::Zero(V.rows(), 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Eigen::RowVector3d n = (b - a).cross(c - a).transpose();
    for (int k = 0; k < 3; ++k) N.row(F(f, k)) += n;
  }
  for (Eigen::Index i = 0; i < N.rows(); ++i) {
    const double length = N.row(i).norm();
    if (length > 0 && std::isfinite(length))
      N.row(i) /= length;
    else
      N.row(i) << 0, 0, 1;
  }
  return N;
}

void uv_tangents(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const Eigen::MatrixX2d& UV,
                 Eigen::MatrixX3d& dPdu, Eigen::MatrixX3d& dPdv) {
  dPdu = Eigen::MatrixX3d::Zero(V.rows(), 3);
  dPdv = Eigen::MatrixX3d::Zero(V.rows(), 3);
  Eigen::VectorXd weight = Eigen::VectorXd::Zero(V.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const int i = F(f, 0), j = F(f, 1), k = F(f, 2);
    const Eigen::Vector3d e1 = V.row(j) - V.row(i), e2 = V.row(k) - V.row(i);
    const Eigen::Vector2d t1 = UV.row(j) - UV.row(i), t2 = UV.row(k) - UV.row(i);
    const double det = t1.x() * t2.y() - t2.x() * t1.y();
    const double area = 0.5 * e1.cross(e2).norm();
    if (std::abs(det) < 1e-14 || !(area > 0)) continue;
    // [e1 e2] = [dPdu dPdv] [t1 t2]  =>  [dPdu dPdv] = [e1 e2] [t1 t2]^-1.
    const Eigen::Vector3d du = (e1 * t2.y() - e2 * t1.y()) / det;
    const Eigen::Vector3d dv = (e2 * t1.x() - e1 * t2.x()) / det;
    for (int v : {i, j, k}) {
      dPdu.row(v) += area * du.transpose();
      dPdv.row(v) += area * dv.transpose();
      weight(v) += area;
    }
  }
  for (Eigen::Index v = 0; v < V.rows(); ++v)
    if (weight(v) > 0) {
      dPdu.row(v) /= weight(v);
      dPdv.row(v) /= weight(v);
    }
}

}  // namespace loom::numerics
