#include "triangle_frames.hpp"

#include <algorithm>
#include <cmath>

namespace loom::arap {

TriangleFrames triangle_frames(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) {
  const Eigen::Index nf = F.rows();
  TriangleFrames fr;
  fr.D.resize(nf, 6);
  fr.cot.resize(nf, 3);
  fr.area.resize(nf);
  for (Eigen::Index t = 0; t < nf; ++t) {
    const Eigen::Vector3d x0 = V.row(F(t, 0)), x1 = V.row(F(t, 1)), x2 = V.row(F(t, 2));
    const Eigen::Vector3d e01 = x1 - x0, e02 = x2 - x0;
    // Isometric frame: x0 at the origin, x1 on the positive x axis.
    Eigen::Vector2d p[3];
    p[0].setZero();
    const double l01 = e01.norm();
    if (l01 > 0) {
      const Eigen::Vector3d ax = e01 / l01;
      const double along = e02.dot(ax);
      p[1] = {l01, 0};
      p[2] = {along, (e02 - along * ax).norm()};
    } else {
      p[1].setZero();
      p[2] = {e02.norm(), 0};
    }
    for (int i = 0; i < 3; ++i) fr.D.block<1, 2>(t, 2 * i) = (p[i] - p[(i + 1) % 3]).transpose();
    const double twice_area = std::abs(p[1].x() * p[2].y() - p[1].y() * p[2].x());
    fr.area[t] = twice_area / 2;
    double longest2 = 0;
    for (int i = 0; i < 3; ++i) longest2 = std::max(longest2, (p[i] - p[(i + 1) % 3]).squaredNorm());
    if (!(twice_area > 1e-8 * longest2)) {
      fr.cot.row(t).setConstant(kDegenerateWeight);
      ++fr.degenerate;
      continue;
    }
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector2d a = p[i] - p[(i + 2) % 3], b = p[(i + 1) % 3] - p[(i + 2) % 3];
      fr.cot(t, i) = a.dot(b) / twice_area;
    }
  }
  return fr;
}

}  // namespace loom::arap
