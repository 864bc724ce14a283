// Scenes and statistics shared by the path tracer's tests.
#pragma once

#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "embree_scene.hpp"
#include "integrator.hpp"
#include "loom/scene.hpp"

namespace loom::pathtrace::test {

// One exact sphere (an Embree sphere point) of the given material at the
// origin, filling the whole view of the camera (fov_y 0.3: the image's
// corners are 12° off axis, the sphere's rim 14.5°).
inline Scene sphere_in_environment(const Material& material, const Environment& environment) {
  Scene scene;
  SceneObject o;
  auto points = std::make_shared<PointSet>();
  points->P = Eigen::MatrixX3d::Zero(1, 3);
  points->radius = Eigen::VectorXd::Constant(1, 1.0);
  o.points = points;
  o.material = material;
  scene.objects.push_back(o);
  scene.environment = environment;
  Camera camera;
  camera.eye = Eigen::Vector3d(0, 0, 4);
  camera.target = Eigen::Vector3d::Zero();
  camera.fov_y = 0.3;
  scene.camera = camera;
  return scene;
}

inline std::shared_ptr<Image> constant_map(int width, int height, float value) {
  return std::make_shared<Image>(cv::Mat(height, width, CV_32FC3, cv::Scalar::all(value)), Encoding::linear);
}

// Per-pixel mean and standard error of the mean over K renders with
// independent seeds (channel 0..2 interleaved as in the image).
struct PixelStatistics {
  cv::Mat mean, standard_error;
};
inline PixelStatistics independent_renders(const Scene& scene, RenderSettings settings, int K) {
  const EmbreeScene traced(scene);
  cv::Mat sum = cv::Mat::zeros(settings.height, settings.width, CV_64FC3), sum2 = sum.clone();
  for (int k = 0; k < K; ++k) {
    settings.seed = 1000 + std::uint64_t(k);
    cv::Mat image;
    render(scene, *scene.camera, traced, settings).image.convertTo(image, CV_64FC3);
    sum += image;
    sum2 += image.mul(image);
  }
  PixelStatistics s;
  s.mean = sum / K;
  cv::Mat var = (sum2 - sum.mul(sum) / K) / (K - 1);
  cv::sqrt(cv::max(var, 0.0) / K, s.standard_error);
  return s;
}

// Mean over K renders with independent seeds (first_seed, first_seed + 1,
// ...) of the image's mean (channels averaged), and its standard error.
struct MeanAndError {
  double mean, se;
};
inline MeanAndError image_mean(const Scene& scene, RenderSettings s, int K, std::uint64_t first_seed) {
  const EmbreeScene traced(scene);
  double sum = 0, sum2 = 0;
  for (int k = 0; k < K; ++k) {
    s.seed = first_seed + std::uint64_t(k);
    const cv::Scalar m = cv::mean(render(scene, *scene.camera, traced, s).image);
    const double v = (m[0] + m[1] + m[2]) / 3;
    sum += v;
    sum2 += v * v;
  }
  const double mean = sum / K;
  return {mean, std::sqrt(std::max(0.0, (sum2 / K - mean * mean) / (K - 1)))};
}

// Chi-square of draw counts against weights (zero weights: no draws allowed,
// checked), with its degrees of freedom.
struct ChiSquare {
  double value = 0;
  int dof = -1;
};
inline ChiSquare chi_square_against_weights(const std::vector<double>& w, const std::vector<int>& count, int n) {
  double sum = 0;
  for (double x : w) sum += x;
  ChiSquare c;
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (w[i] == 0) {
      EXPECT_EQ(count[i], 0) << "index " << i;
      continue;
    }
    const double expected = n * w[i] / sum;
    c.value += (count[i] - expected) * (count[i] - expected) / expected;
    ++c.dof;
  }
  return c;
}

inline int count_nonfinite(const cv::Mat& m) {
  int bad = 0;
  cv::Mat flat = m.reshape(1);
  for (int y = 0; y < flat.rows; ++y)
    for (int x = 0; x < flat.cols; ++x) bad += !std::isfinite(flat.at<float>(y, x));
  return bad;
}

}  // namespace loom::pathtrace::test
