#include "loom/numerics/distortion.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "loom/numerics/svd.hpp"

namespace loom::numerics {

// Per face: the 3D triangle in its own isometric frame P = [p1-p0, p2-p0]
// (p0 at the origin, p1 on the x axis), the UV triangle Q likewise; J = Q P⁻¹.
// Faces with no 3D area have no Jacobian and are left out of every figure
// but `faces`. A face whose UV area is zero or negative is flipped; the angle
// and area figures use |σ2| and skip faces with zero UV area (whose ratios
// are infinite); the ARAP energy uses the signed σ2 (negative when det J < 0),
// so that it is the squared distance from J to the closest rotation.
DistortionReport distortion(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                            const Eigen::MatrixX2d& UV) {
  const int m = static_cast<int>(F.rows());
  DistortionReport r;
  r.faces = m;
  std::vector<Eigen::Matrix2d> P(m), Q(m);
  std::vector<double> area(m, 0.0);
  double total_3d = 0, total_uv = 0;
  for (int f = 0; f < m; ++f) {
    const Eigen::Vector3d e1 = V.row(F(f, 1)) - V.row(F(f, 0));
    const Eigen::Vector3d e2 = V.row(F(f, 2)) - V.row(F(f, 0));
    const double l1 = e1.norm(), doubled = e1.cross(e2).norm();
    if (!(doubled > 1e-12 * (e1.squaredNorm() + e2.squaredNorm()))) continue;
    P[f] << l1, e1.dot(e2) / l1, 0, doubled / l1;
    Q[f].col(0) = (UV.row(F(f, 1)) - UV.row(F(f, 0))).transpose();
    Q[f].col(1) = (UV.row(F(f, 2)) - UV.row(F(f, 0))).transpose();
    area[f] = doubled / 2;
    total_3d += area[f];
    total_uv += std::abs(Q[f].determinant()) / 2;
  }
  if (total_3d == 0) return r;
  const double scale = total_uv > 0 ? std::sqrt(total_3d / total_uv) : 1.0;

  double weight = 0, angle_sum = 0, area_sum = 0, energy = 0;
  for (int f = 0; f < m; ++f) {
    if (area[f] == 0) continue;
    const Eigen::Matrix2d J = scale * Q[f] * P[f].inverse();
    const double det = J.determinant();
    const Eigen::Vector2d s = singular_values_2x2(J);
    const double s2_signed = det < 0 ? -s[1] : s[1];
    energy += area[f] * ((s[0] - 1) * (s[0] - 1) + (s2_signed - 1) * (s2_signed - 1));
    if (det <= 1e-12 * s[0] * s[0]) ++r.flipped;
    if (!(s[1] > 1e-12 * s[0])) continue;
    const double angle = s[0] / s[1];
    const double areal = std::max(s[0] * s[1], 1 / (s[0] * s[1]));
    weight += area[f];
    angle_sum += area[f] * angle;
    area_sum += area[f] * areal;
    r.angle_max = std::max(r.angle_max, angle);
    r.area_max = std::max(r.area_max, areal);
  }
  r.arap_energy = energy / total_3d;
  if (weight > 0) {
    r.angle_mean = angle_sum / weight;
    r.area_mean = area_sum / weight;
  }
  return r;
}

json to_json(const DistortionReport& r) {
  return {{"faces", r.faces},           {"flipped", r.flipped},     {"angle_mean", r.angle_mean},
          {"angle_max", r.angle_max},   {"area_mean", r.area_mean}, {"area_max", r.area_max},
          {"arap_energy", r.arap_energy}};
}

std::string to_string(const DistortionReport& r) {
  char line[256];
  std::snprintf(line, sizeof line,
                "%d faces, %d flipped; angle distortion σ1/σ2 mean %.4g max %.4g; "
                "area distortion mean %.4g max %.4g; ARAP energy %.4g",
                r.faces, r.flipped, r.angle_mean, r.angle_max, r.area_mean, r.area_max,
                r.arap_energy);
  return line;
}

}  // namespace loom::numerics
