#include "view_math.hpp"

#include <algorithm>
#include <cmath>

namespace loom::shading {

Eigen::Matrix4d look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                        const Eigen::Vector3d& up) {
  const Eigen::Vector3d f = (target - eye).normalized();
  Eigen::Vector3d s = f.cross(up);
  if (s.norm() < 1e-9) s = f.cross(std::abs(f.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY());
  s.normalize();
  const Eigen::Vector3d u = s.cross(f);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -s.dot(eye);
  m(1, 3) = -u.dot(eye);
  m(2, 3) = f.dot(eye);
  return m;
}

Eigen::Matrix4d perspective(double fov_y, double aspect, double n, double f) {
  const double t = 1.0 / std::tan(fov_y / 2);
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m(0, 0) = t / aspect;
  m(1, 1) = t;
  m(2, 2) = (f + n) / (n - f);
  m(2, 3) = 2 * f * n / (n - f);
  m(3, 2) = -1;
  return m;
}

Eigen::Matrix4d orthographic(double l, double r, double b, double t, double n, double f) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m(0, 0) = 2 / (r - l);
  m(1, 1) = 2 / (t - b);
  m(2, 2) = -2 / (f - n);
  m(0, 3) = -(r + l) / (r - l);
  m(1, 3) = -(t + b) / (t - b);
  m(2, 3) = -(f + n) / (f - n);
  return m;
}

void camera_matrices(const Camera& camera, double aspect, Eigen::Matrix4d& view,
                     Eigen::Matrix4d& projection) {
  view = look_at(camera.eye, camera.target, camera.up);
  if (camera.projection == Camera::Projection::perspective) {
    projection = perspective(camera.fov_y, aspect, camera.near_plane, camera.far_plane);
  } else {
    const double h = camera.ortho_height / 2, w = h * aspect;
    projection = orthographic(-w, w, -h, h, camera.near_plane, camera.far_plane);
  }
}

namespace {
std::array<Eigen::Vector3d, 8> corners(const Eigen::AlignedBox3d& box) {
  std::array<Eigen::Vector3d, 8> c;
  for (int i = 0; i < 8; ++i)
    c[i] = box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i));
  return c;
}
}  // namespace

ShadowView shadow_view(const Light& light, const Eigen::AlignedBox3d& bounds, int resolution) {
  ShadowView s;
  const Eigen::Vector3d center = bounds.center();
  const double radius = std::max(0.5 * bounds.diagonal().norm(), 1e-6);
  if (light.kind == Light::Kind::directional) {
    s.ortho = true;
    s.axis = light.direction.normalized();
    s.origin = center - s.axis * 2 * radius;
    s.view = look_at(s.origin, center, Eigen::Vector3d::UnitY());
    // The bounds' extent across the light, square texels, a texel of margin.
    double half = 0;
    for (const auto& c : corners(bounds)) {
      const Eigen::Vector4d q = s.view * c.homogeneous();
      half = std::max({half, std::abs(q.x()), std::abs(q.y())});
    }
    half = std::max(half, 1e-6) * (1 + 2.0 / resolution);
    s.near_plane = radius * 0.5;
    s.far_plane = radius * 3.5;
    s.projection = orthographic(-half, half, -half, half, s.near_plane, s.far_plane);
    s.texel = 2 * half / resolution;
    return s;
  }
  s.origin = light.position;
  double far = 0;
  for (const auto& c : corners(bounds)) far = std::max(far, (c - light.position).norm());
  far = std::max(far, 1e-6) * 1.01;
  const double near = far * 1e-4;
  if (light.kind == Light::Kind::spot) {
    s.axis = light.direction.normalized();
    const double fov = std::min(2 * light.spot_outer + 0.05, 3.0);
    s.view = look_at(s.origin, s.origin + s.axis, std::abs(s.axis.y()) < 0.99 ? Eigen::Vector3d::UnitY()
                                                                                : Eigen::Vector3d::UnitX());
    s.projection = perspective(fov, 1, near, far);
    s.texel = 2 * std::tan(fov / 2) / resolution;
    return s;
  }
  s.cube = true;
  s.axis = Eigen::Vector3d::UnitZ();
  s.projection = perspective(M_PI / 2, 1, near, far);
  const Eigen::Vector3d dirs[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const Eigen::Vector3d ups[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
  for (int f = 0; f < 6; ++f) s.faces[f] = look_at(s.origin, s.origin + dirs[f], ups[f]);
  s.texel = 2.0 / resolution;
  return s;
}

}  // namespace loom::shading
