// Back-face culling of closed meshes (closed_surface.hpp): which meshes are
// closed, told from how they were built; and the image with culling against
// the same render of a mesh that is not closed (so nothing is culled).
#include <gtest/gtest.h>

#include "closed_surface.hpp"
#include "gl_api.hpp"
#include "rasterizer.hpp"
#include "shading_scenes.hpp"

namespace loom::shading {
namespace {

Mesh reversed(Mesh m) {
  m.F.col(1).swap(m.F.col(2));
  return m;
}

// The mesh and one more small triangle at its center: open, but never seen
// (inside the sphere) and within its bounds (the shadow map stays fitted alike).
Mesh with_stray_triangle(Mesh m) {
  const Eigen::Index n = m.V.rows();
  m.V.conservativeResize(n + 3, 3);
  m.V.bottomRows(3) << 0, 0, 0, 0.1, 0, 0, 0, 0.1, 0;
  if (m.UV.rows()) {
    m.UV.conservativeResize(n + 3, 2);
    m.UV.bottomRows(3).setZero();
  }
  if (m.N.rows()) {
    m.N.conservativeResize(n + 3, 3);
    m.N.bottomRows(3).setZero();
    m.N.bottomRows(3).col(2).setOnes();
  }
  m.F.conservativeResize(m.F.rows() + 1, 3);
  m.F.bottomRows(1) << int(n), int(n + 1), int(n + 2);
  return m;
}

TEST(ClosedSurface, OrientationOfBuiltMeshes) {
  // A UV sphere: seam vertices duplicated, pole faces degenerate; closed once welded.
  const Mesh ball = scenes::sphere(12, 24);
  EXPECT_EQ(closed_orientation(ball.V, ball.F), 1);
  EXPECT_EQ(closed_orientation(ball.V, reversed(ball).F), -1);
  // A box of 4 own vertices per face (flat normals): closed once welded.
  const Mesh box = scenes::box({-1, 0, -1}, {1, 2, 1});
  EXPECT_EQ(closed_orientation(box.V, box.F), 1);
  // Open: a plane, a sphere less one face, a sphere with a stray triangle.
  const Mesh plane = scenes::plane(4, 1);
  EXPECT_EQ(closed_orientation(plane.V, plane.F), 0);
  EXPECT_EQ(closed_orientation(ball.V, ball.F.topRows(ball.F.rows() - 30)), 0);
  const Mesh stray = with_stray_triangle(ball);
  EXPECT_EQ(closed_orientation(stray.V, stray.F), 0);
  // Two closed parts of opposite orientation: neither side may be culled.
  Mesh two = ball;
  const Mesh inner = reversed(scenes::sphere(12, 24, 0.5));
  two.V.conservativeResize(ball.V.rows() + inner.V.rows(), 3);
  two.V.bottomRows(inner.V.rows()) = inner.V;
  two.F.conservativeResize(ball.F.rows() + inner.F.rows(), 3);
  two.F.bottomRows(inner.F.rows()) = inner.F.array() + int(ball.V.rows());
  EXPECT_EQ(closed_orientation(two.V, two.F), 0);
}

TEST(ClosedSurface, HiddenSideFollowsNearPlaneAndMirroring) {
  const Eigen::AlignedBox3d unit(Eigen::Vector3d::Constant(-1), Eigen::Vector3d::Constant(1));
  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
  view(2, 3) = -3;  // the camera 3 units before the box's center, looking down -z
  const Eigen::Matrix4d id = Eigen::Matrix4d::Identity();
  EXPECT_EQ(hidden_side(1, unit, id, view, 0.1), unsigned(GL_BACK));
  EXPECT_EQ(hidden_side(-1, unit, id, view, 0.1), unsigned(GL_FRONT));
  EXPECT_EQ(hidden_side(0, unit, id, view, 0.1), 0u);
  EXPECT_EQ(hidden_side(1, unit, id, view, 2.5), 0u);  // the near plane cuts the box
  const Eigen::Matrix4d mirror = Eigen::Vector4d(-1, 1, 1, 1).asDiagonal();
  EXPECT_EQ(hidden_side(1, unit, mirror, view, 0.1), unsigned(GL_FRONT));
}

Scene ball_on_floor(const Mesh& ball) {
  Scene s;
  s.objects.push_back(scenes::object(scenes::plane(2, 3)));
  Mesh b = ball;
  b.V.col(1).array() += 1.1;
  s.objects.push_back(scenes::object(b, {0.8, 0.4, 0.3}));
  s.objects.back().material.specular = 0.5;
  Light sun;
  sun.kind = Light::Kind::directional;
  sun.direction = Eigen::Vector3d(-0.5, -1, -0.4).normalized();
  sun.intensity = 3;
  s.lights.push_back(sun);
  Camera c;
  c.eye = {0, 2.5, 5};
  c.target = {0, 0.8, 0};
  c.fov_y = 0.8;
  s.camera = c;
  return s;
}

// Pixels whose colour differs by more than 1/255 in any channel.
int pixels_differing(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat d;
  cv::absdiff(a, b, d);
  cv::Mat worst;
  cv::reduce(d.reshape(1, int(d.total())), worst, 1, cv::REDUCE_MAX);
  return cv::countNonZero(worst > 1.0 / 255);
}

// Culling a closed sphere's hidden side (either winding) leaves the image
// as it is with nothing culled: the same sphere, opened by a triangle
// nobody sees. A sample on the silhouette, where a front and a back face
// meet at equal depth, may take the other face (measured: 1 pixel of
// 129,600, by a quarter of its value); culling the wrong side would change
// thousands.
TEST(ClosedSurface, CullingLeavesTheImage) {
  static Rasterizer r;
  RenderOptions o;
  o.width = 480;
  o.height = 270;
  for (const Mesh& ball : {scenes::sphere(40, 80), reversed(scenes::sphere(40, 80))}) {
    const cv::Mat culled = r.render(ball_on_floor(ball), o).color;
    const cv::Mat open = r.render(ball_on_floor(with_stray_triangle(ball)), o).color;
    cv::Mat d;
    cv::absdiff(culled, open, d);
    EXPECT_LT(cv::mean(d)[0], 1e-4);
    EXPECT_LE(pixels_differing(culled, open), 10);  // of 129,600
  }
}

// A near plane inside a closed sphere opens it: the inside (back faces) must
// still be drawn where the front was clipped.
TEST(ClosedSurface, NearPlaneInsideTheMeshShowsItsInside) {
  static Rasterizer r;
  Scene s;
  s.objects.push_back(scenes::object(scenes::sphere(24, 48)));
  Camera c;
  c.eye = {0, 0, 3};
  c.target = {0, 0, 0};
  c.near_plane = 2.5;  // cuts the sphere's front cap (z > 0.5)
  s.camera = c;
  Light l;
  l.casts_shadow = false;
  s.lights.push_back(l);
  RenderOptions o;
  o.width = o.height = 64;
  o.shadows = ShadowFilter::off;
  const cv::Mat image = r.render(s, o).color;
  EXPECT_EQ(image.at<cv::Vec4f>(32, 32)[3], 1.0f);  // covered: the inside of the far half
}

}  // namespace
}  // namespace loom::shading
