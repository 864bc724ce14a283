// Seamless cloning: time against error to the exact solve (CHOLMOD) for the
// multigrid solver at several tolerances, the exact solve itself, and OpenCV's
// cv::seamlessClone side by side on the same 8-bit images and region; plus the
// drag re-solve (new offset, cached factorization or hierarchy).
//
//   bench_poisson [--quick] [--size N]
//   --quick: no 2048² exact solve, one repeat;  --size N: only N² regions
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include <opencv2/imgproc.hpp>
#include <opencv2/photo.hpp>

#include "bench_harness.hpp"
#include "exact_poisson.hpp"
#include "multigrid.hpp"
#include "poisson_system.hpp"

using namespace loom::poisson;

namespace {

// An 8-bit RGB test image: smooth colour waves plus a fine texture, so both
// the membrane and the guidance gradients matter.
cv::Mat3b pattern(cv::Size size, double phase) {
  cv::Mat3b m(size);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      const double u = x * 6.283 / size.width, v = y * 6.283 / size.height;
      const double t = 0.15 * std::sin(0.9 * x + phase) * std::cos(0.7 * y);
      m(y, x) = cv::Vec3b(cv::saturate_cast<uchar>(255 * (0.5 + 0.3 * std::sin(u + phase) + t)),
                          cv::saturate_cast<uchar>(255 * (0.5 + 0.3 * std::cos(v - phase) - t)),
                          cv::saturate_cast<uchar>(255 * (0.5 + 0.25 * std::sin(u + v + 2 * phase))));
    }
  return m;
}

cv::Mat to_float(const cv::Mat3b& m) {
  cv::Mat f;
  m.convertTo(f, CV_32FC3, 1.0 / 255);
  return f;
}

struct Errors {
  double max = 0, rms = 0;  // in 1/255 levels
};

Errors compare(const cv::Mat& f, const cv::Mat& ref, const cv::Mat1b& unknown) {
  Errors e;
  double sum = 0;
  long n = 0;
  for (int y = 0; y < unknown.rows; ++y)
    for (int x = 0; x < unknown.cols; ++x) {
      if (!unknown(y, x)) continue;
      for (int c = 0; c < 3; ++c) {
        const double d = 255.0 * (f.ptr<float>(y)[x * 3 + c] - ref.ptr<float>(y)[x * 3 + c]);
        e.max = std::max(e.max, std::abs(d));
        sum += d * d;
        ++n;
      }
    }
  e.rms = std::sqrt(sum / n);
  return e;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  int only = 0;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) quick = true;
    if (std::strcmp(argv[i], "--size") == 0 && i + 1 < argc) only = std::atoi(argv[++i]);
  }
  loom::bench::Csv csv("poisson", {"size", "solver", "tolerance", "seconds", "iterations",
                                   "max_error_255", "rms_error_255", "speedup_vs_opencv"});
  loom::bench::Csv drag("poisson_drag", {"size", "solver", "seconds_per_resolve", "fps"});
  const int sizes[] = {256, 512, 1024, 2048};
  const double tolerances[] = {1e-2, 3e-3, 2e-3, 1e-3, 3e-4, 1e-5};
  for (const int N : sizes) {
    if (only && N != only) continue;
    const int runs = quick ? 1 : (N >= 2048 ? 1 : N >= 1024 ? 3 : 5);
    const cv::Size source_size(N + 2, N + 2), target_size(N + 64, N + 64);
    const cv::Mat3b src8 = pattern(source_size, 0.0), dst8 = pattern(target_size, 1.7);
    const cv::Mat source = to_float(src8), target = to_float(dst8);
    cv::Mat1b mask = cv::Mat1b::zeros(source_size);
    mask(cv::Rect(1, 1, N, N)).setTo(255);
    const cv::Point offset(31, 31);
    const BlendRegion region = place_region(mask, offset, target_size);
    const cv::Mat b = poisson_rhs(region, target, source, offset, Guidance::normal);
    const cv::Mat guess = source_on_rect(region, source, offset);

    // The exact reference (factor + solve).
    cv::Mat exact = guess.clone();
    const bool run_exact = !(quick && N >= 2048);
    double exact_seconds = NAN;
    std::unique_ptr<ExactPoisson> factor;
    if (run_exact) {
      const auto t = loom::bench::time_median(
          [&] {
            factor = std::make_unique<ExactPoisson>(region.unknown);
            factor->solve(poisson_rhs(region, target, source, offset, Guidance::normal), exact);
          },
          N >= 1024 ? 1 : 3);
      exact_seconds = t.median;
    }

    // OpenCV: the same region, placed by its bounding-box centre.
    cv::Mat3b src_bgr, dst_bgr, out_bgr;
    cv::cvtColor(src8, src_bgr, cv::COLOR_RGB2BGR);
    cv::cvtColor(dst8, dst_bgr, cv::COLOR_RGB2BGR);
    const int len = N - 1;  // OpenCV takes the bounding box as max − min
    const cv::Point centre(1 + offset.x + len / 2, 1 + offset.y + len / 2);
    const auto t_cv = loom::bench::time_median(
        [&] { cv::seamlessClone(src_bgr, dst_bgr, mask, centre, out_bgr, cv::NORMAL_CLONE); }, runs);
    cv::Mat3b out_rgb;
    cv::cvtColor(out_bgr, out_rgb, cv::COLOR_BGR2RGB);
    const cv::Mat opencv = to_float(out_rgb)(region.rect);
    const Errors e_cv = run_exact ? compare(opencv, exact, region.unknown) : Errors{NAN, NAN};
    csv.row({(long long)N, "opencv", 0.0, t_cv.median, 0LL, e_cv.max, e_cv.rms, 1.0});
    if (run_exact)
      csv.row({(long long)N, "cholmod", 0.0, exact_seconds, 1LL, 0.0, 0.0, t_cv.median / exact_seconds});

    for (const double tol : tolerances) {
      cv::Mat f;
      MultigridPoisson::Result result;
      const auto t = loom::bench::time_median(
          [&] {
            f = source_on_rect(region, source, offset);
            MultigridPoisson mg(region.unknown);
            result = mg.solve(poisson_rhs(region, target, source, offset, Guidance::normal), f, tol, 200);
          },
          runs);
      const Errors e = run_exact ? compare(f, exact, region.unknown) : Errors{NAN, NAN};
      csv.row({(long long)N, "multigrid", tol, t.median, (long long)result.iterations, e.max, e.rms,
               t_cv.median / t.median});
    }

    // Drag: a new offset re-solves with the cached hierarchy or factorization.
    if (N <= 1024) {
      const MultigridPoisson mg(region.unknown);
      int shift = 0;
      auto resolve = [&](auto&& solve) {
        const cv::Point moved = offset + cv::Point(shift % 3 - 1, 0);
        ++shift;
        cv::Mat f = source_on_rect(region, source, moved);
        solve(poisson_rhs(region, target, source, moved, Guidance::normal), f);
      };
      const auto t_mg = loom::bench::time_median(
          [&] { resolve([&](const cv::Mat& bb, cv::Mat& f) { mg.solve(bb, f, 1e-4, 200); }); }, 5);
      drag.row({(long long)N, "multigrid", t_mg.median, 1.0 / t_mg.median});
      if (factor) {
        const auto t_ex = loom::bench::time_median(
            [&] { resolve([&](const cv::Mat& bb, cv::Mat& f) { factor->solve(bb, f); }); }, 5);
        drag.row({(long long)N, "cholmod", t_ex.median, 1.0 / t_ex.median});
      }
    }
  }
  csv.save();
  drag.save();
  loom::bench::plot(csv, {"seconds", "max_error_255", "size", "PoissonBlend: first-solve time vs max error (1/255 levels)", true, true, ""});
  return 0;
}
