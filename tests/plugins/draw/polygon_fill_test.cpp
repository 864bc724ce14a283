// Scan-line coverage against analytic areas, exact fractional coverages, the
// two fill rules, and OpenCV's fillPoly as a peer for the aliased case.
#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "polygon_fill.hpp"

namespace loom::draw {
namespace {

double shoelace(const std::vector<Eigen::Vector2d>& p) {
  double a = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto& u = p[i];
    const auto& v = p[(i + 1) % p.size()];
    a += u.x() * v.y() - v.x() * u.y();
  }
  return std::abs(a) / 2;
}

TEST(PolygonFill, AntialiasedCoverageSumsToTheArea) {
  // A rotated square and an irregular convex polygon, well inside the image.
  const double c = std::cos(0.3), s = std::sin(0.3);
  std::vector<Eigen::Vector2d> square;
  for (auto [x, y] : {std::pair{-40.0, -40.0}, {40.0, -40.0}, {40.0, 40.0}, {-40.0, 40.0}})
    square.emplace_back(64.3 + c * x - s * y, 70.1 + s * x + c * y);
  const std::vector<Eigen::Vector2d> irregular = {{10.2, 12.7}, {90.9, 20.1}, {110.4, 95.5}, {30.3, 120.8}};
  for (const auto& poly : {square, irregular}) {
    const cv::Mat cov = polygon_coverage(poly, {140, 140}, FillRule::nonzero, true);
    EXPECT_NEAR(cv::sum(cov)[0], shoelace(poly), 1e-3 * shoelace(poly));
    double lo, hi;
    cv::minMaxLoc(cov, &lo, &hi);
    EXPECT_GE(lo, 0.0);
    EXPECT_LE(hi, 1.0);
  }
}

TEST(PolygonFill, FractionalEdgesGiveExactCoverage) {
  // x in [10.25, 20.75], y in [5.5, 9.0]: sub-scanlines resolve y exactly here.
  const cv::Mat cov =
      polygon_coverage({{10.25, 5.5}, {20.75, 5.5}, {20.75, 9.0}, {10.25, 9.0}}, {32, 16}, FillRule::evenodd, true);
  EXPECT_FLOAT_EQ(cov.at<float>(5, 10), 0.75f * 0.5f);
  EXPECT_FLOAT_EQ(cov.at<float>(5, 15), 0.5f);
  EXPECT_FLOAT_EQ(cov.at<float>(7, 15), 1.0f);
  EXPECT_FLOAT_EQ(cov.at<float>(8, 20), 0.75f);
  EXPECT_FLOAT_EQ(cov.at<float>(9, 15), 0.0f);
  EXPECT_FLOAT_EQ(cov.at<float>(7, 21), 0.0f);
}

TEST(PolygonFill, RulesDifferOnAPentagram) {
  const std::vector<Eigen::Vector2d> star = {{128, 16}, {194, 218}, {22, 94}, {234, 94}, {62, 218}};
  for (bool aa : {false, true}) {
    const cv::Mat even = polygon_coverage(star, {256, 256}, FillRule::evenodd, aa);
    const cv::Mat nonzero = polygon_coverage(star, {256, 256}, FillRule::nonzero, aa);
    EXPECT_EQ(even.at<float>(130, 128), 0.0f);  // the inner pentagon
    EXPECT_EQ(nonzero.at<float>(130, 128), 1.0f);
    EXPECT_EQ(even.at<float>(40, 128), 1.0f);  // a point of the star
    EXPECT_EQ(nonzero.at<float>(40, 128), 1.0f);
  }
}

TEST(PolygonFill, AliasedMatchesOpenCVFillPolyInside) {
  const std::vector<Eigen::Vector2d> poly = {{20, 10}, {100, 30}, {90, 110}, {15, 80}};
  const cv::Mat ours = polygon_coverage(poly, {128, 128}, FillRule::nonzero, false);
  // OpenCV puts pixel centers at integers: move the vertices by −0.5 (1/16 px fixed point).
  std::vector<cv::Point> pts;
  for (const auto& p : poly) pts.emplace_back(int(std::lround((p.x() - 0.5) * 16)), int(std::lround((p.y() - 0.5) * 16)));
  cv::Mat theirs = cv::Mat::zeros(128, 128, CV_8U);
  cv::fillPoly(theirs, std::vector<std::vector<cv::Point>>{pts}, 255, cv::LINE_8, 4);
  cv::Mat ours8;
  ours.convertTo(ours8, CV_8U, 255);
  // OpenCV's fill also paints the pixels its outline passes through: ours is
  // inside it, and the two differ by at most a pixel along the perimeter.
  EXPECT_EQ(cv::countNonZero(ours8 & ~theirs), 0);
  EXPECT_LE(cv::countNonZero(theirs & ~ours8), 340);  // the perimeter is 334 px
  EXPECT_NEAR(cv::countNonZero(ours8), shoelace(poly), 170);
}

TEST(PolygonFill, DegeneratePolygonsCoverNothing) {
  EXPECT_EQ(cv::countNonZero(polygon_coverage({{1, 1}, {5, 5}}, {8, 8}, FillRule::nonzero, true)), 0);
  EXPECT_EQ(cv::countNonZero(polygon_coverage({{1, 1}, {3, 3}, {6, 6}}, {8, 8}, FillRule::nonzero, true)), 0);
  const cv::Mat all = polygon_coverage({{-10, -10}, {100, -10}, {100, 100}, {-10, 100}}, {8, 8}, FillRule::nonzero, true);
  EXPECT_EQ(cv::countNonZero(all == 1.0f), 64);
}

}  // namespace
}  // namespace loom::draw
