// Scenes shared by the shading tests and bench/shading: generated meshes
// with exact descriptions (a sphere, a plane, boxes) so that references can
// be computed independently of the rasterizer.
#pragma once

#include <cmath>
#include <memory>

#include "generators.hpp"
#include "loom/mesh.hpp"
#include "loom/scene.hpp"

namespace loom::shading::scenes {

// Unit-radius UV sphere (rings x segments quads), outward normals = positions.
inline Mesh sphere(int rings, int segments, double radius = 1) {
  Mesh m;
  m.V.resize((rings + 1) * (segments + 1), 3);
  m.UV.resize(m.V.rows(), 2);
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s <= segments; ++s) {
      const double theta = M_PI * r / rings, phi = 2 * M_PI * s / segments;
      const int i = r * (segments + 1) + s;
      m.V.row(i) << std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi);
      m.UV.row(i) << double(s) / segments, 1 - double(r) / rings;
    }
  m.N = m.V;
  m.V *= radius;
  m.F.resize(2 * rings * segments, 3);
  int f = 0;
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const int a = r * (segments + 1) + s, b = a + segments + 1;
      m.F.row(f++) << a, b, a + 1;
      m.F.row(f++) << a + 1, b, b + 1;
    }
  return m;
}

// Square [-h, h]² in the xz plane at height y, facing +y, n x n quads, UV in [0,1]².
inline Mesh plane(int n, double h, double y = 0) {
  return generate::grid_mesh(n, n, [&](double u, double v) {
    return Eigen::Vector3d(-h + 2 * h * u, y, h - 2 * h * v);
  });
}

// Axis-aligned box [lo, hi]: 6 faces of 4 own vertices (flat normals), 12 triangles, outward.
inline Mesh box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  Mesh m;
  m.V.resize(24, 3);
  m.N.resize(24, 3);
  m.F.resize(12, 3);
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int face = 2 * axis + side, a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
      Eigen::Vector3d n = Eigen::Vector3d::Zero();
      n[axis] = side ? 1 : -1;
      for (int k = 0; k < 4; ++k) {
        Eigen::Vector3d p;
        p[axis] = side ? hi[axis] : lo[axis];
        p[a1] = (k & 1) ? hi[a1] : lo[a1];
        p[a2] = (k & 2) ? hi[a2] : lo[a2];
        m.V.row(4 * face + k) = p.transpose();
        m.N.row(4 * face + k) = n.transpose();
      }
      // (a1, a2, axis) is right-handed: counter-clockwise seen from +axis.
      const int b = 4 * face;
      if (side) {
        m.F.row(2 * face) << b, b + 1, b + 3;
        m.F.row(2 * face + 1) << b, b + 3, b + 2;
      } else {
        m.F.row(2 * face) << b, b + 3, b + 1;
        m.F.row(2 * face + 1) << b, b + 2, b + 3;
      }
    }
  return m;
}

inline SceneObject object(Mesh mesh, const Eigen::Vector3d& color = {0.8, 0.8, 0.8}) {
  SceneObject o;
  o.mesh = std::make_shared<const Mesh>(std::move(mesh));
  o.material.base_color = color;
  o.material.specular = 0;
  return o;
}

// A plane, two boxes and a sphere on it, lit by one light: the shadow scene.
inline Scene shadow_scene(Light::Kind kind) {
  Scene s;
  s.objects.push_back(object(plane(8, 4)));
  s.objects.push_back(object(box({-1.5, 0, -0.5}, {-0.5, 1.2, 0.5})));
  s.objects.push_back(object(box({0.6, 0.5, -1.2}, {1.4, 0.8, -0.4})));
  Mesh ball = sphere(48, 96, 0.5);
  ball.V.col(1).array() += 0.9;
  ball.V.col(0).array() += 1.0;
  ball.V.col(2).array() += 1.0;
  s.objects.push_back(object(ball));
  Light l;
  l.kind = kind;
  l.intensity = kind == Light::Kind::directional ? 3 : 60;
  l.position = {2.5, 5, 2};
  l.direction = -l.position.normalized();
  l.spot_inner = 0.6;
  l.spot_outer = 0.8;
  s.lights.push_back(l);
  Camera c;
  c.eye = {0, 6, 7};
  c.target = {0, 0, 0};
  c.fov_y = 0.75;
  s.camera = c;
  return s;
}

}  // namespace loom::shading::scenes
