// The Poisson system and its two solvers against an independent reference:
// the assignment's equation written out pixel by pixel and solved densely.
#include <cmath>
#include <random>

#include <Eigen/Dense>
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "exact_poisson.hpp"
#include "loom/error.hpp"
#include "multigrid.hpp"
#include "poisson_system.hpp"

namespace loom::poisson {
namespace {

cv::Mat random_image(cv::Size size, int channels, unsigned seed) {
  cv::Mat m(size, CV_MAKETYPE(CV_32F, channels));
  cv::theRNG().state = seed;
  cv::randu(m, 0.0, 1.0);
  cv::GaussianBlur(m, m, {0, 0}, 1.5);  // some smooth structure besides noise
  return m;
}

// |N_p| f_p − Σ_{q∈N_p∩Ω} f_q = Σ_{q∈N_p∩∂Ω} f*_q + Σ_{q∈N_p} v_pq, written
// directly in target coordinates and solved densely: shares no code with the
// library beyond reading the inputs.
cv::Mat reference_blend(const cv::Mat& source, const cv::Mat& target, const cv::Mat1b& mask,
                        cv::Point offset, Guidance mode) {
  const int C = target.channels(), W = target.cols, H = target.rows;
  auto in_omega = [&](int x, int y) {
    const int sx = x - offset.x, sy = y - offset.y;
    return x >= 0 && y >= 0 && x < W && y < H && sx > 0 && sy > 0 && sx < source.cols - 1 &&
           sy < source.rows - 1 && mask(sy, sx);
  };
  cv::Mat1i id(H, W, -1);
  int n = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      if (in_omega(x, y)) id(y, x) = n++;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n), B = Eigen::MatrixXd::Zero(n, C);
  const int dx[4] = {-1, 1, 0, 0}, dy[4] = {0, 0, -1, 1};
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int i = id(y, x);
      if (i < 0) continue;
      for (int k = 0; k < 4; ++k) {
        const int qx = x + dx[k], qy = y + dy[k];
        if (qx < 0 || qy < 0 || qx >= W || qy >= H) continue;
        A(i, i) += 1;
        if (id(qy, qx) >= 0) A(i, id(qy, qx)) -= 1;
        for (int c = 0; c < C; ++c) {
          const double fp = target.ptr<float>(y)[x * C + c], fq = target.ptr<float>(qy)[qx * C + c];
          const double gp = source.ptr<float>(y - offset.y)[(x - offset.x) * C + c];
          const double gq = source.ptr<float>(qy - offset.y)[(qx - offset.x) * C + c];
          double v = gp - gq;
          if (mode == Guidance::mixed && std::abs(fp - fq) > std::abs(v)) v = fp - fq;
          B(i, c) += v + (id(qy, qx) < 0 ? fq : 0.0);
        }
      }
    }
  const Eigen::MatrixXd X = A.ldlt().solve(B);
  cv::Mat out = target.clone();
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      if (id(y, x) >= 0)
        for (int c = 0; c < C; ++c) out.ptr<float>(y)[x * C + c] = float(X(id(y, x), c));
  return out;
}

enum class Solver { exact, multigrid };

cv::Mat blend(const cv::Mat& source, const cv::Mat& target, const cv::Mat1b& mask, cv::Point offset,
              Guidance mode, Solver solver, BlendRegion* placed = nullptr) {
  const BlendRegion r = place_region(mask, offset, target.size());
  const cv::Mat b = poisson_rhs(r, target, source, offset, mode);
  cv::Mat f = source_on_rect(r, source, offset);
  if (solver == Solver::exact) {
    ExactPoisson(r.unknown).solve(b, f);
  } else {
    const MultigridPoisson mg(r.unknown);
    mg.solve(b, f, 1e-6, 200);
  }
  cv::Mat out = target.clone();
  f.copyTo(out(r.rect), r.unknown);
  if (placed) *placed = r;
  return out;
}

double max_diff(const cv::Mat& a, const cv::Mat& b) { return cv::norm(a, b, cv::NORM_INF); }

cv::Mat1b disk_with_hole(cv::Size size) {
  cv::Mat1b m = cv::Mat1b::zeros(size);
  const cv::Point c(size.width / 2, size.height / 2);
  cv::circle(m, c, std::min(size.width, size.height) / 2 - 3, 255, cv::FILLED);
  cv::circle(m, c, std::min(size.width, size.height) / 6, 0, cv::FILLED);  // an island of target
  return m;
}

TEST(PoissonSystem, BothSolversMatchTheDenseReferenceOnAnAnnulus) {
  const cv::Mat source = random_image({40, 36}, 3, 1), target = random_image({60, 50}, 3, 2);
  const cv::Mat1b mask = disk_with_hole(source.size());
  for (Guidance mode : {Guidance::normal, Guidance::mixed}) {
    const cv::Mat ref = reference_blend(source, target, mask, {9, 7}, mode);
    EXPECT_LT(max_diff(blend(source, target, mask, {9, 7}, mode, Solver::exact), ref), 1e-5);
    EXPECT_LT(max_diff(blend(source, target, mask, {9, 7}, mode, Solver::multigrid), ref), 1e-4);
  }
}

TEST(PoissonSystem, MultigridMatchesExactOnALargerRegionWithSeveralLevels) {
  const cv::Mat source = random_image({260, 200}, 3, 3), target = random_image({300, 260}, 3, 4);
  const cv::Mat1b mask = disk_with_hole(source.size());
  const BlendRegion r = place_region(mask, {20, 30}, target.size());
  ASSERT_GT(MultigridPoisson(r.unknown).levels(), 2);
  const cv::Mat exact = blend(source, target, mask, {20, 30}, Guidance::normal, Solver::exact);
  const cv::Mat fast = blend(source, target, mask, {20, 30}, Guidance::normal, Solver::multigrid);
  EXPECT_LT(max_diff(exact, fast), 0.5 / 255);
  // The default tolerance of the node keeps the error under half a level too.
  cv::Mat f = source_on_rect(r, source, {20, 30});
  MultigridPoisson(r.unknown).solve(poisson_rhs(r, target, source, {20, 30}, Guidance::normal), f, 2e-3, 200);
  cv::Mat out = target.clone();
  f.copyTo(out(r.rect), r.unknown);
  EXPECT_LT(max_diff(exact, out), 0.5 / 255);
}

TEST(PoissonSystem, WarmStartedDragStaysWithinHalfALevelOfExactWhateverTheHistory) {
  // A drag on one hierarchy, each solve starting from the previous correction,
  // including a return to the first offset and a long jump; the region keeps
  // its shape (no clipping), so the node would reuse the hierarchy the same way.
  const cv::Mat source = random_image({260, 200}, 3, 6), target = random_image({300, 260}, 3, 7);
  const cv::Mat1b mask = disk_with_hole(source.size());
  const cv::Point path[] = {{20, 30}, {21, 30}, {23, 31}, {20, 30}, {-20, 55}, {20, 30}};
  const MultigridPoisson dragged(place_region(mask, path[0], target.size()).unknown);
  ASSERT_GT(dragged.levels(), 2);
  for (Guidance mode : {Guidance::normal, Guidance::mixed})
    for (const cv::Point offset : path) {
      const BlendRegion r = place_region(mask, offset, target.size());
      const cv::Mat b = poisson_rhs(r, target, source, offset, mode);
      cv::Mat warm = source_on_rect(r, source, offset), cold = warm.clone(), exact = warm.clone();
      const auto result = dragged.solve(b, warm, 2e-3, 200, MultigridPoisson::Start::previous_correction);
      EXPECT_LE(result.last_change, 2e-3);
      MultigridPoisson(r.unknown).solve(b, cold, 2e-3, 200);
      ExactPoisson(r.unknown).solve(b, exact);
      EXPECT_LT(max_diff(warm, exact), 0.5 / 255) << "offset " << offset;
      EXPECT_LT(max_diff(warm, cold), 0.5 / 255) << "offset " << offset;
    }
  // A one-channel image after the three-channel drag: the extra lanes of the
  // previous correction must not leak in.
  cv::Mat gray_source, gray_target;
  cv::extractChannel(source, gray_source, 1);
  cv::extractChannel(target, gray_target, 2);
  const BlendRegion r = place_region(mask, path[1], target.size());
  const cv::Mat b = poisson_rhs(r, gray_target, gray_source, path[1], Guidance::normal);
  cv::Mat warm = source_on_rect(r, gray_source, path[1]), exact = warm.clone();
  dragged.solve(b, warm, 2e-3, 200, MultigridPoisson::Start::previous_correction);
  ExactPoisson(r.unknown).solve(b, exact);
  EXPECT_LT(max_diff(warm, exact), 0.5 / 255);
}

TEST(PoissonSystem, MultigridPreconditionerConvergesInFewIterations) {
  // A broken (non-symmetric or inexact) V-cycle still converges in CG, only
  // slowly: the iteration count is what shows it.
  const cv::Mat source = random_image({260, 200}, 3, 8), target = random_image({300, 260}, 3, 9);
  const BlendRegion r = place_region(disk_with_hole(source.size()), {20, 30}, target.size());
  cv::Mat f = source_on_rect(r, source, {20, 30});
  const auto result = MultigridPoisson(r.unknown).solve(
      poisson_rhs(r, target, source, {20, 30}, Guidance::normal), f, 1e-6, 200);
  EXPECT_LE(result.last_change, 1e-6);
  EXPECT_LE(result.iterations, 12);
}

TEST(PoissonSystem, BlendingAnImageIntoItselfReproducesIt) {
  const cv::Mat image = random_image({80, 70}, 3, 5);
  const cv::Mat1b mask = disk_with_hole(image.size());
  for (Solver s : {Solver::exact, Solver::multigrid})
    EXPECT_LT(max_diff(blend(image, image, mask, {0, 0}, Guidance::normal, s), image), 1e-4);
}

TEST(PoissonSystem, AConstantAddedToTheSourceChangesNothingInNormalMode) {
  const cv::Mat source = random_image({50, 40}, 3, 6), target = random_image({70, 60}, 3, 7);
  const cv::Mat1b mask = disk_with_hole(source.size());
  const cv::Mat shifted = source + cv::Scalar::all(0.37);
  for (Solver s : {Solver::exact, Solver::multigrid})
    EXPECT_LT(max_diff(blend(source, target, mask, {5, 8}, Guidance::normal, s),
                       blend(shifted, target, mask, {5, 8}, Guidance::normal, s)),
              1e-4);
}

TEST(PoissonSystem, MixedModePicksTheStrongerGradientPerEdge) {
  const cv::Mat textured = random_image({50, 40}, 1, 8);
  const cv::Mat flat(textured.size(), CV_32FC1, cv::Scalar(0.5));
  const cv::Mat1b mask = disk_with_hole(textured.size());
  // A flat source: the target's gradients win everywhere, the target is kept.
  EXPECT_LT(max_diff(blend(flat, textured, mask, {0, 0}, Guidance::mixed, Solver::exact), textured), 1e-5);
  // A flat target: the source's gradients win, as in normal mode.
  EXPECT_LT(max_diff(blend(textured, flat, mask, {0, 0}, Guidance::mixed, Solver::exact),
                     blend(textured, flat, mask, {0, 0}, Guidance::normal, Solver::exact)),
            1e-5);
  // One pixel, edge by edge: right edge source |0.5| > target |0.1|, others target.
  cv::Mat1f g = cv::Mat1f::zeros(3, 3), t = cv::Mat1f::zeros(3, 3);
  g(1, 2) = -0.5f;                       // g_p − g_q = 0.5 to the right
  t(0, 1) = -0.3f;                       // f*_p − f*_q = 0.3 upwards
  t(1, 2) = -0.1f;
  cv::Mat1b one = cv::Mat1b::zeros(3, 3);
  one(1, 1) = 255;
  const BlendRegion r = place_region(one, {0, 0}, {3, 3});
  const cv::Mat b = poisson_rhs(r, t, g, {0, 0}, Guidance::mixed);
  // Σ f*_q (−0.3 − 0.1) + Σ v (0.5 + 0.3): 0.4.
  EXPECT_NEAR(b.at<float>(1, 1), 0.4f, 1e-6);
}

TEST(PoissonSystem, OnePixelRegionIsTheMeanOfItsEquation) {
  const cv::Mat source = random_image({9, 9}, 3, 9), target = random_image({12, 12}, 3, 10);
  cv::Mat1b mask = cv::Mat1b::zeros(source.size());
  mask(4, 4) = 255;
  const cv::Mat out = blend(source, target, mask, {2, 3}, Guidance::normal, Solver::multigrid);
  const cv::Point p(6, 7);
  for (int c = 0; c < 3; ++c) {
    double sum = 0;
    for (cv::Point d : {cv::Point(-1, 0), cv::Point(1, 0), cv::Point(0, -1), cv::Point(0, 1)})
      sum += target.at<cv::Vec3f>(p + d)[c] + source.at<cv::Vec3f>(4, 4)[c] -
             source.at<cv::Vec3f>(cv::Point(4, 4) + d)[c];
    EXPECT_NEAR(out.at<cv::Vec3f>(p)[c], sum / 4, 1e-6);
  }
}

TEST(PoissonSystem, RegionOnTheTargetBorderUsesFewerNeighbours) {
  const cv::Mat source = random_image({30, 30}, 3, 11), target = random_image({40, 40}, 3, 12);
  cv::Mat1b mask = cv::Mat1b::zeros(source.size());
  mask(cv::Rect(1, 1, 28, 28)).setTo(255);
  const cv::Point offset(-1, 5);  // column 1 lands on target column 0
  BlendRegion r;
  const cv::Mat ref = reference_blend(source, target, mask, offset, Guidance::normal);
  for (Solver s : {Solver::exact, Solver::multigrid}) {
    EXPECT_LT(max_diff(blend(source, target, mask, offset, Guidance::normal, s, &r), ref), 1e-4);
    EXPECT_FALSE(r.clipped_target);
  }
  // Pushed further, part of it falls off the target and is clipped.
  const cv::Mat clipped_ref = reference_blend(source, target, mask, {-10, 20}, Guidance::normal);
  EXPECT_LT(max_diff(blend(source, target, mask, {-10, 20}, Guidance::normal, Solver::multigrid, &r),
                     clipped_ref),
            1e-4);
  EXPECT_TRUE(r.clipped_target);
}

TEST(PoissonSystem, SourceBorderPixelsAreLeftOut) {
  const cv::Mat source = random_image({20, 20}, 3, 13), target = random_image({40, 40}, 3, 14);
  const cv::Mat1b mask(source.size(), uchar(255));  // the whole source
  BlendRegion r;
  const cv::Mat out = blend(source, target, mask, {10, 10}, Guidance::normal, Solver::exact, &r);
  EXPECT_TRUE(r.clipped_source);
  EXPECT_EQ(r.count, 18 * 18);
  EXPECT_LT(max_diff(out, reference_blend(source, target, mask, {10, 10}, Guidance::normal)), 1e-5);
  cv::Mat1b rim = cv::Mat1b::zeros(source.size());
  rim.row(0).setTo(255);
  EXPECT_THROW(place_region(rim, {0, 0}, target.size()), Error);
}

TEST(PoissonSystem, DegenerateRegionsAreClearErrors) {
  EXPECT_THROW(place_region(cv::Mat1b::zeros(10, 10), {0, 0}, {20, 20}), Error);  // empty
  cv::Mat1b mask = cv::Mat1b::zeros(10, 10);
  mask(cv::Rect(2, 2, 5, 5)).setTo(255);
  EXPECT_THROW(place_region(mask, {100, 0}, {20, 20}), Error);  // lands outside
  // Ω would be the whole 3×3 target: nothing to fix the solution.
  EXPECT_THROW(place_region(mask, {-3, -3}, {3, 3}), Error);
  try {
    place_region(cv::Mat1b::zeros(10, 10), {0, 0}, {20, 20});
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("mask is empty"), std::string::npos);
  }
}

TEST(PoissonSystem, RegionKeyFollowsTheShapeNotThePlace) {
  cv::Mat1b mask = cv::Mat1b::zeros(30, 30);
  cv::circle(mask, {15, 15}, 10, 255, cv::FILLED);
  const std::uint64_t a = region_key(place_region(mask, {10, 10}, {100, 100}));
  EXPECT_EQ(a, region_key(place_region(mask, {40, 20}, {100, 100})));
  cv::circle(mask, {15, 15}, 3, 0, cv::FILLED);
  EXPECT_NE(a, region_key(place_region(mask, {10, 10}, {100, 100})));
}

}  // namespace
}  // namespace loom::poisson
