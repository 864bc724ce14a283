// Degenerate and large inputs: never a crash, a singular-matrix failure or a
// NaN pixel. Runs the real node through the engine for the degenerate pair
// sets, and the core for the large cases (a 4096² image, 2,000 pairs).
#include <chrono>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "control_points.hpp"
#include "idw.hpp"
#include "loom/image.hpp"
#include "loom/testing.hpp"
#include "rbf.hpp"
#include "warp_image.hpp"

namespace loom {
namespace {

std::vector<json> degenerate_pair_sets() {
  return {
      json::array(),                                                        // 0 points
      json::array({{50, 50, 60, 55}}),                                      // 1
      json::array({{50, 50, 60, 55}, {100, 80, 90, 100}}),                  // 2
      json::array({{10, 10, 12, 12}, {60, 60, 70, 70}, {110, 110, 100, 100}}),  // 3 collinear
      json::array({{10, 10, 20, 10}, {100, 10, 90, 30}, {50, 100, 50, 90}}),    // 3 in general position
      json::array({{50, 50, 60, 55}, {50, 50, 40, 45}, {50.0000001, 50, 55, 50}, {90, 90, 95, 80}}),  // duplicates
      json::array({{50, 50, 60, 55}, {50.01, 50, 40, 45}, {90, 90, 95, 80}}),  // 0.01 px apart: kept, still finite
      json::array({{-500, -400, -450, -400}, {900, 1200, 1000, 1250}, {60, 60, 64, 58}}),  // outside the image
      json::array({{50, 50, 50, 50}, {90, 60, 90, 60}, {70, 100, 70, 100}}),  // identity
      json::array({{10, 50, 30, 50}, {20, 50, 20, 70}, {30, 50, 40, 40}, {40, 50, 50, 60}}),  // collinear sources
      json::array({{50, 50, 60, 60}, {100, 80, 60, 60}, {60, 110, 60, 60}}),  // all targets equal (fold)
  };
}

TEST(WarpStress, DegeneratePairsNeverGiveNaNThroughTheNode) {
  testing::Engine e;
  const json board = {{"type", "Checkerboard"}, {"inputs", {{"size", {128, 128}}, {"cells", 4}}}};
  int set = 0;
  for (const json& pairs : degenerate_pair_sets()) {
    for (const char* method : {"idw", "rbf"})
      for (const char* kernel : {"multiquadric", "thin_plate"})
        for (const char* mode : {"inverse", "forward"})
          for (double mu : {1.0, 2.0}) {
            json inputs = {{"image", {{"from", "board.image"}}}, {"pairs", pairs}, {"method", method},
                           {"rbf_kernel", kernel}, {"mode", mode}, {"rbf_exponent", mu}, {"idw_power", mu}};
            const json g = {{"loom", 1}, {"nodes", {{"board", board}, {"warp", {{"type", "ImageWarp"}, {"inputs", inputs}}}}}};
            SCOPED_TRACE("set " + std::to_string(set) + " " + method + " " + kernel + " " + mode + " mu " +
                         std::to_string(mu));
            const Image& out = e.output<Image>(g, "warp.image");
            EXPECT_TRUE(cv::checkRange(out.pixels));
          }
    ++set;
  }
}

TEST(WarpStress, NaNCoordinatesAreDroppedNotPropagated) {
  Eigen::MatrixX2d P(3, 2), Q(3, 2);
  P << 10, 10, NAN, 40, 80, 20;
  Q << 12, 14, 30, 30, 70, 25;
  std::vector<std::string> notes;
  const warp::ControlPoints cp = warp::clean_control_points(P, Q, 1e-3, &notes);
  ASSERT_EQ(cp.p.rows(), 2);
  const warp::RbfMap m = warp::fit_rbf(cp.p, cp.q, warp::RbfKernel::multiquadric, 1, 0, &notes);
  const warp::IdwMap d = warp::fit_idw(cp.p, cp.q, 2, true);
  Eigen::MatrixX2d X(3, 2);
  X << 0, 0, 10, 10, 1e4, -1e4;
  EXPECT_TRUE(warp::evaluate_rbf(m, X).allFinite());
  EXPECT_TRUE(warp::evaluate_idw(d, X).allFinite());
}

TEST(WarpStress, LargeImageAndManyPairs) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 4096), jitter(-20, 20);
  const int n = 2000;
  Eigen::MatrixX2d P(n, 2), Q(n, 2);
  for (int i = 0; i < n; ++i) {
    P.row(i) << u(rng), u(rng);
    Q.row(i) = P.row(i) + Eigen::RowVector2d(jitter(rng), jitter(rng));
  }
  const auto start = std::chrono::steady_clock::now();
  std::vector<std::string> notes;
  const warp::ControlPoints cp = warp::clean_control_points(Q, P, 1e-3, &notes);
  const warp::RbfMap m = warp::fit_rbf(cp.p, cp.q, warp::RbfKernel::multiquadric, 1, 0, &notes);
  EXPECT_LE((warp::evaluate_rbf(m, cp.p) - cp.q).cwiseAbs().maxCoeff(), 1e-6);
  const warp::RowMap f = [&m](double y, const double* x, int k, double* fx, double* fy) {
    warp::evaluate_rbf_row(m, y, x, k, fx, fy);
  };
  cv::Mat src(4096, 4096, CV_32FC3, cv::Scalar(0.5, 0.25, 0.75));
  const cv::Mat out = warp::inverse_warp(src, f, src.size(), 16, warp::Outside::background, cv::Scalar::all(1), {});
  EXPECT_TRUE(cv::checkRange(out));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  RecordProperty("seconds", std::to_string(seconds));
  EXPECT_LT(seconds, 60.0);
}

}  // namespace
}  // namespace loom
