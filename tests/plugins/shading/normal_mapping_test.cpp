// Normal and displacement mapping against true geometry: a finely
// tessellated plane displaced on the CPU (normals from its own triangles)
// against the flat plane with the matching normal map, and against
// displacement by the tessellation shaders.
#include <gtest/gtest.h>

#include "height_maps.hpp"
#include "rasterizer.hpp"
#include "shading_scenes.hpp"
#include "loom/numerics/tangent_frames.hpp"

namespace loom::shading {
namespace {

Rasterizer& rasterizer() {
  static Rasterizer r;
  return r;
}

TEST(HeightMaps, RampGivesTheAnalyticNormal) {
  cv::Mat h(32, 64, CV_32FC1);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) h.at<float>(y, x) = float(0.3 * (x + 0.5) / 64 + 0.2 * (1 - (y + 0.5) / 32));
  // z = s (0.3 u + 0.2 v): n ~ (-0.3 s, -0.2 s, 1).
  const double s = 0.7;
  const cv::Mat n = height_to_normal_map(h, s, false);
  const Eigen::Vector3d expected = Eigen::Vector3d(-0.3 * s, -0.2 * s, 1).normalized();
  for (int y = 1; y < 31; ++y)
    for (int x = 1; x < 63; ++x) {
      const cv::Vec3f c = n.at<cv::Vec3f>(y, x);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(2 * c[k] - 1, expected[k], 1e-5);
    }
}

TEST(HeightMaps, BricksAndBumpsTileAndStayInRange) {
  for (const cv::Mat& h : {brick_height(256, 128, 8, 4, 0.12, 0.15), bump_height(128, 128, 4, 4)}) {
    double lo, hi;
    cv::minMaxLoc(h, &lo, &hi);
    EXPECT_GE(lo, 0.0);
    EXPECT_LE(hi, 1.0);
    EXPECT_LT(lo, 0.05);
    EXPECT_GT(hi, 0.95);
    // Seamless: the first and last columns/rows continue each other.
    EXPECT_LT(cv::norm(h.col(0), h.col(h.cols - 1), cv::NORM_INF), 0.3);
  }
}

struct Views {
  Scene scene;
  Mesh flat;
};

// A 2x2 plane seen from straight above (orthographic), a grazing sun.
Scene top_view() {
  Scene s;
  Light sun;
  sun.kind = Light::Kind::directional;
  sun.direction = Eigen::Vector3d(-1, -0.3, 0.2).normalized();
  sun.intensity = 3;
  sun.casts_shadow = false;
  s.lights.push_back(sun);
  s.environment.color = {0.05, 0.05, 0.05};
  Camera c;
  c.projection = Camera::Projection::orthographic;
  c.eye = {0, 5, 0};
  c.target = {0, 0, 0};
  c.up = {0, 0, -1};
  c.ortho_height = 1.6;
  c.near_plane = 0.1;
  c.far_plane = 20;
  s.camera = c;
  return s;
}

double mean_difference(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat d;
  cv::absdiff(a, b, d);
  const cv::Scalar m = cv::mean(d);
  return (m[0] + m[1] + m[2]) / 3;
}

TEST(NormalMapping, MatchesTrueDisplacedGeometryUnderAGrazingLight) {
  const cv::Mat height = bump_height(512, 512, 4, 4);
  const double scale = 0.08;  // displacement, scene units; the UV square is 2 units wide
  auto height_image = std::make_shared<Image>(height, Encoding::linear);
  auto normal_image = std::make_shared<Image>(height_to_normal_map(height, scale / 2, true), Encoding::linear);

  // True geometry: a 384² grid, each vertex moved along +y by scale * h(uv)
  // (bilinear lookup), normals from the displaced triangles.
  Mesh displaced = scenes::plane(384, 1);
  for (Eigen::Index i = 0; i < displaced.V.rows(); ++i) {
    const double fx = displaced.UV(i, 0) * 512 - 0.5, fy = (1 - displaced.UV(i, 1)) * 512 - 0.5;
    const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
    const double ax = fx - x0, ay = fy - y0;
    auto at = [&](int x, int y) { return double(height.at<float>((y + 512) % 512, (x + 512) % 512)); };
    const double h = (1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x0 + 1, y0)) +
                     ay * ((1 - ax) * at(x0, y0 + 1) + ax * at(x0 + 1, y0 + 1));
    displaced.V(i, 1) += scale * h;
  }
  displaced.N = numerics::vertex_normals(displaced.V, displaced.F);

  RenderOptions o;
  o.width = o.height = 256;
  o.shadows = ShadowFilter::off;
  Scene truth = top_view(), mapped = top_view(), flat = top_view();
  truth.objects.push_back(scenes::object(displaced));
  SceneObject m = scenes::object(scenes::plane(16, 1));
  flat.objects.push_back(m);
  m.material.normal_map = normal_image;
  mapped.objects.push_back(m);
  const cv::Mat a = rasterizer().render(truth, o).color;
  const cv::Mat b = rasterizer().render(mapped, o).color;
  const cv::Mat c = rasterizer().render(flat, o).color;
  const double mapped_error = mean_difference(a, b), flat_error = mean_difference(a, c);
  RecordProperty("normal_map_mean_difference", std::to_string(mapped_error));
  RecordProperty("flat_mean_difference", std::to_string(flat_error));
  EXPECT_LT(mapped_error, 0.15 * flat_error) << mapped_error << " vs flat " << flat_error;

  // Displacement by tessellation: same shading as the true geometry.
  Scene tess = top_view();
  SceneObject d = scenes::object(scenes::plane(16, 1));
  d.material.displacement_map = height_image;
  d.material.displacement_scale = scale;
  tess.objects.push_back(d);
  o.tessellation = 32;
  o.aux = true;
  const RenderImages t = rasterizer().render(tess, o);
  const double tess_error = mean_difference(a, t.color);
  RecordProperty("tessellation_mean_difference", std::to_string(tess_error));
  EXPECT_LT(tess_error, 0.15 * flat_error) << tess_error << " vs flat " << flat_error;
  // ... and the same heights: depth from the camera at y = 5 is 5 - y.
  Scene truth_aux = truth;
  const RenderImages ta = rasterizer().render(truth_aux, o);
  cv::Mat dt, da;
  cv::extractChannel(t.position, dt, 1);
  cv::extractChannel(ta.position, da, 1);
  EXPECT_LT(cv::norm(dt, da, cv::NORM_L1) / dt.total(), 0.05 * scale);
}

}  // namespace
}  // namespace loom::shading
