// Normal and displacement maps in the path tracer, against the geometry they
// stand for: a flat quad whose normal map encodes a constant tilted normal
// shades like the geometrically tilted quad (and like Lambert's law, in closed
// form, under a directional light); a plane displaced by a constant map is
// the translated plane.
#include <cmath>

#include <gtest/gtest.h>

#include "displacement.hpp"
#include "normal_mapping.hpp"
#include "test_scenes.hpp"

namespace {

using namespace loom::pathtrace;
using loom::Material;

constexpr double kPiD = 3.14159265358979323846;

// The square [-1, 1]² of the plane y = 0, facing +y; u along +x, v along -z
// (so the tangent frame is T = +x, B = -z, n = +y).
std::shared_ptr<loom::Mesh> quad(const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity(),
                                 double y = 0) {
  auto m = std::make_shared<loom::Mesh>();
  Eigen::MatrixX3d V0(4, 3);
  V0 << -1, y, -1, 1, y, -1, 1, y, 1, -1, y, 1;
  m->UV.resize(4, 2);
  for (int i = 0; i < 4; ++i) m->UV.row(i) << (V0(i, 0) + 1) / 2, (1 - V0(i, 2)) / 2;
  m->V = V0 * R.transpose();
  m->F.resize(2, 3);
  m->F << 0, 2, 1, 0, 3, 2;
  return m;
}

loom::Scene lit_from_above(std::shared_ptr<loom::Mesh> mesh, const Material& material,
                           const Eigen::Vector3d& to_light) {
  loom::Scene scene;
  loom::SceneObject o;
  o.name = "quad";
  o.mesh = std::move(mesh);
  o.material = material;
  scene.objects.push_back(o);
  loom::Light sun;
  sun.kind = loom::Light::Kind::directional;
  sun.direction = -to_light.normalized();
  sun.intensity = 2;
  scene.lights.push_back(sun);
  loom::Camera camera;
  camera.projection = loom::Camera::Projection::orthographic;
  camera.eye = Eigen::Vector3d(0, 5, 0);
  camera.target = Eigen::Vector3d::Zero();
  camera.up = Eigen::Vector3d(0, 0, -1);
  camera.ortho_height = 0.5;
  scene.camera = camera;
  return scene;
}

RenderSettings direct_only(int size) {
  RenderSettings s;
  s.width = s.height = size;
  s.spp = 4;
  s.max_depth = 1;
  return s;
}

TEST(NormalMap, ConstantTiltShadesLikeTheTiltedQuad) {
  const double a = 0.5;  // tilt of the normal about z, towards +x
  const Eigen::Vector3d tilted(std::sin(a), std::cos(a), 0);
  const Eigen::Vector3d to_light = Eigen::Vector3d(0.8, 1, 0.3).normalized();
  Material lambert;
  lambert.base_color = Eigen::Vector3d(0.5, 0.4, 0.3);
  const double cos_l = tilted.dot(to_light);
  ASSERT_GT(cos_l, 0.5);

  Material mapped = lambert;
  // Tangent space: m = (sin a, 0, cos a) encoded as (m + 1) / 2.
  mapped.normal_map = std::make_shared<loom::Image>(
      cv::Mat(4, 4, CV_32FC3,
              cv::Scalar((std::sin(a) + 1) / 2, 0.5, (std::cos(a) + 1) / 2)),
      loom::Encoding::linear);
  const loom::Scene flat = lit_from_above(quad(), mapped, to_light);
  Eigen::Matrix3d R;
  R << std::cos(a), std::sin(a), 0, -std::sin(a), std::cos(a), 0, 0, 0, 1;
  ASSERT_LT((R * Eigen::Vector3d(0, 1, 0) - tilted).norm(), 1e-12);
  const loom::Scene geometric = lit_from_above(quad(R), lambert, to_light);

  const RenderSettings s = direct_only(8);
  const EmbreeScene traced_flat(flat), traced_geometric(geometric);
  const RenderResult rf = render(flat, *flat.camera, traced_flat, s);
  const RenderResult rg = render(geometric, *geometric.camera, traced_geometric, s);
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x)
      for (int c = 0; c < 3; ++c) {
        // Lambert under a directional light of irradiance E: L = ρ/π E cos θ.
        const double expected = lambert.base_color[c] / kPiD * 2 * cos_l;
        EXPECT_NEAR(rf.image.at<cv::Vec3f>(y, x)[c], expected, 1e-5 * (1 + expected)) << x << "," << y;
        EXPECT_NEAR(rg.image.at<cv::Vec3f>(y, x)[c], expected, 1e-5 * (1 + expected)) << x << "," << y;
      }
  // The normal AOV is the mapped normal.
  const cv::Vec3f n = rf.normal.at<cv::Vec3f>(4, 4);
  EXPECT_NEAR(n[0], tilted.x(), 1e-5);
  EXPECT_NEAR(n[1], tilted.y(), 1e-5);
  EXPECT_NEAR(n[2], tilted.z(), 1e-5);
}

TEST(NormalMap, FlatMapChangesNothing) {
  // (0.5, 0.5, 1) encodes the unperturbed normal: the same image as no map,
  // with indirect light and noise (same seeds, same random numbers).
  Material plain;
  Material mapped = plain;
  mapped.normal_map = std::make_shared<loom::Image>(cv::Mat(2, 2, CV_32FC3, cv::Scalar(0.5, 0.5, 1.0)),
                                                    loom::Encoding::linear);
  const Eigen::Vector3d to_light(0.3, 1, 0.2);
  const loom::Scene a = lit_from_above(quad(), plain, to_light), b = lit_from_above(quad(), mapped, to_light);
  RenderSettings s = direct_only(6);
  s.max_depth = 4;
  const EmbreeScene ta(a), tb(b);
  const cv::Mat ia = render(a, *a.camera, ta, s).image, ib = render(b, *b.camera, tb, s).image;
  EXPECT_LT(cv::norm(ia, ib, cv::NORM_INF), 1e-6);
}

TEST(NormalMap, BendKeepsTheViewerAboveTheHorizon) {
  const Vec3f ng(0, 0, 1);
  for (int i = 0; i < 200; ++i) {
    const float t = 0.05f + 1.4f * float(i) / 200;  // mapped normal tilted by t from ng
    const Vec3f ns(std::sin(t), 0, std::cos(t));
    for (float side : {1.f, -1.f}) {
      const Vec3f wo = Vec3f(-0.9f, 0.1f, side * 0.3f).normalized();
      const Vec3f bent = bend_above_horizon(ns, ng, wo);
      EXPECT_NEAR(bent.norm(), 1, 1e-5);
      // On wo's side of the surface, wo is above the bent horizon.
      EXPECT_GT(side * bent.dot(wo), 0) << t;
      if (side > 0 && ns.dot(wo) >= 0.01f) {
        EXPECT_EQ(bent, ns);  // no bend needed
      }
    }
  }
}

TEST(Displacement, SubdivisionSharesMidpoints) {
  // The square in two triangles, subdivided L times: the (2^L + 1)² grid, no
  // duplicated midpoints (no cracks).
  loom::Mesh m = *quad();
  for (int level = 1; level <= 3; ++level) {
    m = subdivide_midpoint(m);
    const int side = (1 << level) + 1;
    EXPECT_EQ(m.V.rows(), side * side);
    EXPECT_EQ(m.F.rows(), 2 * (1 << (2 * level)));
    EXPECT_EQ(m.UV.rows(), m.V.rows());
    for (Eigen::Index v = 0; v < m.V.rows(); ++v) {
      // UVs stay the linear function of the position they were.
      EXPECT_NEAR(m.UV(v, 0), (m.V(v, 0) + 1) / 2, 1e-12);
      EXPECT_NEAR(m.UV(v, 1), (1 - m.V(v, 2)) / 2, 1e-12);
    }
  }
}

TEST(Displacement, ConstantMapIsTheTranslatedPlane) {
  const double h = 0.3, scale = 2;  // every vertex moves by 0.6 along +y
  const auto map = std::make_shared<loom::Image>(cv::Mat(5, 7, CV_32FC1, cv::Scalar(h)), loom::Encoding::linear);
  const loom::Mesh d = displaced_mesh(*quad(), *map, scale, 3);
  const loom::Mesh reference = subdivide_midpoint(subdivide_midpoint(subdivide_midpoint(*quad(Eigen::Matrix3d::Identity(), h * scale))));
  ASSERT_EQ(d.V.rows(), reference.V.rows());
  EXPECT_LT((d.V - reference.V).cwiseAbs().maxCoeff(), 1e-6);  // the map is read in float
  for (Eigen::Index v = 0; v < d.N.rows(); ++v) EXPECT_NEAR(d.N(v, 1), 1, 1e-12);

  // Rendered: the depth seen from y = 5 is 5 - 0.6 everywhere, as for the
  // plane moved there by its transform.
  Material displaced;
  displaced.displacement_map = map;
  displaced.displacement_scale = scale;
  loom::Scene a = lit_from_above(quad(), displaced, Eigen::Vector3d(0, 1, 0));
  loom::Scene b = lit_from_above(quad(), Material(), Eigen::Vector3d(0, 1, 0));
  b.objects[0].transform(1, 3) = h * scale;
  const RenderSettings s = direct_only(8);
  const EmbreeScene ta(a, 2), tb(b), off(a, 0);
  EXPECT_EQ(ta.triangles(), 2u * 16);
  const cv::Mat da = render(a, *a.camera, ta, s).depth, db = render(b, *b.camera, tb, s).depth;
  const cv::Mat d0 = render(a, *a.camera, off, s).depth;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      EXPECT_NEAR(da.at<float>(y, x), 5 - h * scale, 1e-4);
      EXPECT_NEAR(db.at<float>(y, x), 5 - h * scale, 1e-4);
      EXPECT_NEAR(d0.at<float>(y, x), 5, 1e-4);  // level 0: displacement off
    }
  EXPECT_NE(geometry_key(a, 2), geometry_key(a, 0));
  EXPECT_NE(geometry_key(a, 2), geometry_key(a, 3));
}

}  // namespace
