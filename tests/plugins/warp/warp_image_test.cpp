// Moving pixels: inverse sampling, forward splatting and crack filling,
// checked against analytic maps (identity, translations, affine).
#include <random>

#include <gtest/gtest.h>

#include "warp_image.hpp"

namespace loom::warp {
namespace {

cv::Mat random_image(cv::Size size, int type, unsigned seed) {
  cv::Mat m(size, type);
  cv::RNG rng(seed);
  rng.fill(m, cv::RNG::UNIFORM, 0.2, 0.8);  // never the white background
  return m;
}

RowMap affine(double a00, double a01, double a10, double a11, double bx, double by) {
  return [=](double y, const double* x, int n, double* fx, double* fy) {
    for (int j = 0; j < n; ++j) {
      fx[j] = a00 * x[j] + a01 * y + bx;
      fy[j] = a10 * x[j] + a11 * y + by;
    }
  };
}

const cv::Scalar kWhite(1, 1, 1, 1);

TEST(WarpImage, InverseIdentityIsExact) {
  for (int type : {CV_32FC1, CV_32FC3, CV_32FC4}) {
    const cv::Mat src = random_image({37, 23}, type, 1);
    const cv::Mat out = inverse_warp(src, affine(1, 0, 0, 1, 0, 0), src.size(), 1, Outside::background, kWhite, {});
    EXPECT_EQ(cv::norm(out, src, cv::NORM_INF), 0.0);
  }
}

TEST(WarpImage, InverseIntegerTranslationShifts) {
  const cv::Mat src = random_image({40, 30}, CV_32FC3, 2);
  // out(x) = src(x + (3, 2)).
  const cv::Mat out = inverse_warp(src, affine(1, 0, 0, 1, 3, 2), src.size(), 1, Outside::background, kWhite, {});
  EXPECT_EQ(cv::norm(out(cv::Rect(0, 0, 37, 28)), src(cv::Rect(3, 2, 37, 28)), cv::NORM_INF), 0.0);
  // What maps outside the source is background, and nothing is NaN.
  EXPECT_EQ(out.at<cv::Vec3f>(29, 39), cv::Vec3f(1, 1, 1));
  EXPECT_TRUE(cv::checkRange(out));
}

TEST(WarpImage, InterpolatedMapIsExactForAffineMaps) {
  const cv::Mat src = random_image({101, 67}, CV_32FC3, 3);
  const RowMap f = affine(0.9, 0.1, -0.05, 1.1, 4.25, -2.5);
  const cv::Mat exact = inverse_warp(src, f, src.size(), 1, Outside::replicate, kWhite, {});
  const cv::Mat coarse = inverse_warp(src, f, src.size(), 8, Outside::replicate, kWhite, {});
  EXPECT_LE(cv::norm(exact, coarse, cv::NORM_INF), 1e-5);
}

TEST(WarpImage, ForwardMagnificationCracksAndFillRemovesThem) {
  const cv::Mat src = random_image({200, 200}, CV_32FC3, 4);
  // Scale by 1.5 about the center: the whole output is covered by the image.
  const RowMap f = affine(1.5, 0, 0, 1.5, -50, -50);
  Splat s = forward_warp(src, f, src.size(), 1, kWhite, {});
  auto white_pixels = [](const cv::Mat& m) {
    cv::Mat white;
    cv::inRange(m, cv::Scalar(1, 1, 1), cv::Scalar(1, 1, 1), white);
    return cv::countNonZero(white);
  };
  EXPECT_GT(white_pixels(s.image), 5000);  // the "white lines"
  EXPECT_NEAR(s.max_stretch, 1.5, 1e-6);
  const int filled = fill_cracks(s.image, s.written, 2);
  EXPECT_GT(filled, 5000);
  EXPECT_EQ(white_pixels(s.image), 0);
  EXPECT_EQ(cv::countNonZero(s.written), 200 * 200);
}

TEST(WarpImage, FillKeepsTheBackgroundAroundAShrunkImage) {
  const cv::Mat src = random_image({100, 100}, CV_32FC1, 5);
  Splat s = forward_warp(src, affine(0.5, 0, 0, 0.5, 25, 25), src.size(), 1, kWhite, {});
  fill_cracks(s.image, s.written, 2);
  EXPECT_EQ(s.image.at<float>(5, 5), 1.0f);    // outside the shrunk copy
  EXPECT_NE(s.image.at<float>(50, 50), 1.0f);  // inside it
}

}  // namespace
}  // namespace loom::warp
