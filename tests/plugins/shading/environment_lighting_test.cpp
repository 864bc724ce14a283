// Environment lighting of Render against references computed here: the
// irradiance of a Lambertian unit sphere under a non-uniform lat-long map by
// direct quadrature over every texel, the old ambient term for a uniform
// environment, and the mirror direction of a glossy sphere's highlight.
#include <gtest/gtest.h>

#include <cmath>

#include "irradiance_sh.hpp"
#include "rasterizer.hpp"
#include "shading_scenes.hpp"

namespace loom::shading {
namespace {

Rasterizer& rasterizer() {
  static Rasterizer r;
  return r;
}

const Eigen::Vector3d sun_direction = Eigen::Vector3d(0.5, 0.6, 0.4).normalized();
constexpr double sun_radius = 0.2;  // radians
constexpr double sun_radiance = 30;

// A sky gradient above a dim ground, plus a bright disk: radiance by world
// direction (the map is filled through loom::latlong_direction).
Eigen::Vector3d sky(const Eigen::Vector3d& d, double disk = sun_radiance) {
  if (std::acos(std::clamp(d.dot(sun_direction), -1.0, 1.0)) < sun_radius) return Eigen::Vector3d::Constant(disk);
  if (d.y() < 0) return Eigen::Vector3d(0.3, 0.25, 0.2) * (0.5 + 0.3 * d.x());
  return Eigen::Vector3d(0.2, 0.4, 0.9) * (0.4 + 0.6 * d.y());
}

std::shared_ptr<const Image> sky_map(int width, int height, double rotation, double disk = sun_radiance) {
  cv::Mat px(height, width, CV_32FC3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const Eigen::Vector3d L = sky(latlong_direction({(x + 0.5) / width, (y + 0.5) / height}, rotation), disk);
      px.at<cv::Vec3f>(y, x) = cv::Vec3f(float(L.x()), float(L.y()), float(L.z()));
    }
  return std::make_shared<Image>(px, Encoding::linear);
}

// Irradiance at normal n by quadrature over every texel of the map:
// E(n) = sum L(w) max(0, n.w) dw, with each texel's exact solid angle.
Eigen::Vector3d quadrature_irradiance(const Image& map, double rotation, const Eigen::Vector3d& n) {
  const int W = map.width(), H = map.height();
  Eigen::Vector3d E = Eigen::Vector3d::Zero();
  for (int y = 0; y < H; ++y) {
    const double dw = 2 * M_PI / W * (std::cos(M_PI * y / H) - std::cos(M_PI * (y + 1) / H));
    for (int x = 0; x < W; ++x) {
      const Eigen::Vector3d w = latlong_direction({(x + 0.5) / W, (y + 0.5) / H}, rotation);
      const double c = n.dot(w);
      if (c <= 0) continue;
      const cv::Vec3f L = map.pixels.at<cv::Vec3f>(y, x);
      E += Eigen::Vector3d(L[0], L[1], L[2]) * (c * dw);
    }
  }
  return E;
}

struct SphereView {
  Scene scene;
  Camera camera;
  int width = 200, height = 160;
};

SphereView sphere_view(const Material& material) {
  SphereView v;
  SceneObject ball = scenes::object(scenes::sphere(128, 256));
  ball.material = material;
  v.scene.objects.push_back(ball);
  v.camera.eye = {0.3, 0.4, 4};
  v.camera.target = {0, 0, 0};
  v.camera.fov_y = 0.7;
  v.camera.near_plane = 0.1;
  v.camera.far_plane = 100;
  v.scene.camera = v.camera;
  return v;
}

// Calls f(x, y, n, d) for every pixel whose center ray hits the unit sphere
// well inside its silhouette (n the exact normal, d the ray direction).
template <class F>
void for_sphere_pixels(const SphereView& v, F f) {
  const Camera& cam = v.camera;
  const Eigen::Vector3d fwd = (cam.target - cam.eye).normalized();
  const Eigen::Vector3d s = fwd.cross(cam.up).normalized(), u = s.cross(fwd);
  const double t = std::tan(cam.fov_y / 2), aspect = double(v.width) / v.height;
  for (int y = 0; y < v.height; ++y)
    for (int x = 0; x < v.width; ++x) {
      const double px = (2 * (x + 0.5) / v.width - 1) * t * aspect, py = (1 - 2 * (y + 0.5) / v.height) * t;
      const Eigen::Vector3d d = (fwd + px * s + py * u).normalized();
      const double b = cam.eye.dot(d), c = cam.eye.squaredNorm() - 1, disc = b * b - c;
      if (disc < 0.05) continue;
      f(x, y, Eigen::Vector3d(cam.eye + (-b - std::sqrt(disc)) * d), d);
    }
}

RenderImages render(const SphereView& v) {
  RenderOptions o;
  o.width = v.width;
  o.height = v.height;
  o.shadows = ShadowFilter::off;
  return rasterizer().render(v.scene, o);
}

Material lambertian(const Eigen::Vector3d& albedo) {
  Material m;
  m.model = Material::Model::diffuse;
  m.base_color = albedo;
  m.specular = 0;
  return m;
}

struct IrradianceErrors {
  double mean = 0, worst = 0;  // absolute, relative to the largest irradiance on the sphere (R&H's measure)
  double mean_of_mean = 0;     // mean absolute error relative to the mean irradiance
  double render_vs_sh = 0;     // the GPU's SH sum against the CPU's, relative to the largest
};

// Renders a Lambertian unit sphere lit by `map` only, compares every pixel with
// albedo / pi * intensity * E(n), E by quadrature over the map's texels.
IrradianceErrors irradiance_errors(std::shared_ptr<const Image> map, double rotation) {
  const Eigen::Vector3d albedo(0.9, 0.7, 0.5);
  const double intensity = 1.5;
  SphereView v = sphere_view(lambertian(albedo));
  v.scene.environment.map = map;
  v.scene.environment.rotation = rotation;
  v.scene.environment.intensity = intensity;
  const RenderImages r = render(v);
  const Sh9 E9 = sh9_irradiance_coefficients(sh9_project(*map, rotation));
  double sum_error = 0, sum_reference = 0, worst = 0, largest = 0, worst_sh = 0;
  int compared = 0;
  for_sphere_pixels(v, [&](int x, int y, const Eigen::Vector3d& n, const Eigen::Vector3d&) {
    const Eigen::Vector3d expected = albedo.cwiseProduct(quadrature_irradiance(*map, rotation, n)) * (intensity / M_PI);
    const Eigen::Vector3d sh = albedo.cwiseProduct(sh9_irradiance(E9, n)) * (intensity / M_PI);
    const cv::Vec4f p = r.color.at<cv::Vec4f>(y, x);
    for (int k = 0; k < 3; ++k) {
      const double e = std::abs(p[k] - expected[k]);
      sum_error += e;
      sum_reference += expected[k];
      worst = std::max(worst, e);
      largest = std::max(largest, expected[k]);
      worst_sh = std::max(worst_sh, std::abs(p[k] - sh[k]));
    }
    ++compared;
  });
  EXPECT_GT(compared, 5000);
  IrradianceErrors out;
  out.mean = sum_error / (3 * compared) / largest;
  out.worst = worst / largest;
  out.mean_of_mean = sum_error / sum_reference;
  out.render_vs_sh = worst_sh / largest;
  std::printf("SH-9 vs quadrature over %d pixels: mean %.2f%%, worst %.2f%% of the largest irradiance; mean %.2f%% "
              "of the mean; render vs CPU SH sum %.3f%%\n",
              compared, 100 * out.mean, 100 * out.worst, 100 * out.mean_of_mean, 100 * out.render_vs_sh);
  return out;
}

// SH-9 irradiance (R&H 2001) against the quadrature. R&H measure the error
// against the largest irradiance: about 1-3% on average for any lighting,
// under 9% at worst (a directional light, the hardest case). Accepted here,
// for a sky gradient with a bright disk (0.2 rad, two thirds of the light: near
// that hardest case): mean <= 3%, worst <= 9%; the same sky without the disk:
// mean <= 1%, worst <= 3%. The render's SH sum equals the CPU's within 0.5%
// (RGBA16F samples).
TEST(EnvironmentLighting, LambertSphereMatchesQuadratureOfTheMap) {
  const IrradianceErrors sun = irradiance_errors(sky_map(128, 64, 0.7), 0.7);
  EXPECT_LE(sun.mean, 0.03);
  EXPECT_LE(sun.worst, 0.09);
  EXPECT_LE(sun.render_vs_sh, 0.005);
  const IrradianceErrors smooth = irradiance_errors(sky_map(128, 64, 0.7, 0), 0.7);
  EXPECT_LE(smooth.mean, 0.01);
  EXPECT_LE(smooth.worst, 0.03);
  EXPECT_LE(smooth.render_vs_sh, 0.005);
}

// The projection itself: a map that is one SH basis function comes back as
// that coefficient alone (orthonormality, by the texels' solid angles).
TEST(EnvironmentLighting, ProjectionOfABasisFunctionIsThatCoefficient) {
  for (int k = 0; k < 9; ++k) {
    cv::Mat px(128, 256, CV_32FC1);
    for (int y = 0; y < px.rows; ++y)
      for (int x = 0; x < px.cols; ++x)
        px.at<float>(y, x) = float(sh9_basis(latlong_direction({(x + 0.5) / px.cols, (y + 0.5) / px.rows}))[k]);
    const Sh9 L = sh9_project(Image(px, Encoding::linear), 0);
    for (int j = 0; j < 9; ++j) EXPECT_NEAR(L[j].x(), j == k ? 1.0 : 0.0, 2e-3) << "basis " << k << " coefficient " << j;
  }
}

// A uniform environment is the old ambient term: radiance albedo * color,
// whether given as a color or as a constant map (then through SH: E = pi L).
TEST(EnvironmentLighting, UniformEnvironmentIsTheAmbientTerm) {
  const Eigen::Vector3d albedo(0.9, 0.7, 0.5), color(0.4, 0.6, 0.8);
  SphereView v = sphere_view(lambertian(albedo));
  v.scene.environment.color = color;
  v.scene.environment.intensity = 2;
  const RenderImages by_color = render(v);
  cv::Mat constant(32, 64, CV_32FC3, cv::Scalar(color.x(), color.y(), color.z()));
  v.scene.environment.map = std::make_shared<Image>(constant, Encoding::linear);
  const RenderImages by_map = render(v);
  int compared = 0;
  for_sphere_pixels(v, [&](int x, int y, const Eigen::Vector3d&, const Eigen::Vector3d&) {
    const Eigen::Vector3d expected = 2 * albedo.cwiseProduct(color);
    for (int k = 0; k < 3; ++k) {
      // RGBA16F samples: 11 significant bits.
      EXPECT_NEAR(by_color.color.at<cv::Vec4f>(y, x)[k], expected[k], 1e-3 * expected[k]) << x << " " << y;
      EXPECT_NEAR(by_map.color.at<cv::Vec4f>(y, x)[k], expected[k], 3e-3 * expected[k]) << x << " " << y;
    }
    ++compared;
  });
  EXPECT_GT(compared, 5000);
}

// A smooth conductor mirrors the map: its brightest pixel is where the mirror
// direction reflect(d, n) points into the bright disk, and a diffuse material
// shows no such reflection (only SH irradiance, which is smooth).
TEST(EnvironmentLighting, GlossySphereReflectsTheBrightDisk) {
  Material metal;
  metal.model = Material::Model::conductor;
  metal.base_color = {0.9, 0.9, 0.9};
  metal.specular = 1;
  metal.roughness = 0.1;
  SphereView v = sphere_view(metal);
  v.scene.environment.map = sky_map(256, 128, 0);
  const RenderImages r = render(v);
  double brightest = -1;
  Eigen::Vector3d mirror_at_brightest = Eigen::Vector3d::Zero();
  for_sphere_pixels(v, [&](int x, int y, const Eigen::Vector3d& n, const Eigen::Vector3d& d) {
    const double value = r.color.at<cv::Vec4f>(y, x)[1];
    if (value > brightest) {
      brightest = value;
      mirror_at_brightest = d - 2 * d.dot(n) * n;
    }
  });
  EXPECT_LT(std::acos(std::clamp(mirror_at_brightest.dot(sun_direction), -1.0, 1.0)), sun_radius)
      << "the highlight's mirror direction misses the bright disk";
  // Bright: the disk seen through a level of the mip chain narrower than the disk.
  EXPECT_GT(brightest, 0.3 * 0.9 * sun_radiance);
}

}  // namespace
}  // namespace loom::shading
