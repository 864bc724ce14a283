// Seamless cloning: time against error to the exact solve (CHOLMOD) for the
// multigrid solver at several tolerances, the exact solve itself, and OpenCV's
// cv::seamlessClone side by side on the same 8-bit images and region (OpenCV
// and each tolerance alternating run by run); plus the
// drag re-solve (new offset, cached factorization or hierarchy).
//
//   bench_poisson [--quick] [--size N] [first] [drag]
//   --quick: no 2048² exact solve, one repeat;  drag: only the drag re-solve;
//   first: only the first solve;  --size N: only N² regions
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/photo.hpp>

#include "alternating.hpp"
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

// The inputs of size N as 8-bit PNG files (lossless: the bench's images are 8-bit).
void write_inputs(const std::string& dir, int N, const cv::Mat3b& source_rgb, const cv::Mat3b& target_rgb,
                  const cv::Mat1b& mask) {
  cv::Mat3b source_bgr, target_bgr;
  cv::cvtColor(source_rgb, source_bgr, cv::COLOR_RGB2BGR);
  cv::cvtColor(target_rgb, target_bgr, cv::COLOR_RGB2BGR);
  const std::string n = std::to_string(N);
  if (!cv::imwrite(dir + "/source-" + n + ".png", source_bgr) ||
      !cv::imwrite(dir + "/target-" + n + ".png", target_bgr) || !cv::imwrite(dir + "/mask-" + n + ".png", mask))
    throw std::runtime_error("cannot write the inputs into " + dir);
}

// Wall median (time_median) and mean process CPU seconds (all threads) per call.
struct WallCpu {
  double wall = 0, cpu = 0;
};
template <class F>
WallCpu time_wall_cpu(F&& f, int runs) {
  const std::clock_t start = std::clock();
  const double wall = loom::bench::time_median(f, runs).median;
  return {wall, double(std::clock() - start) / CLOCKS_PER_SEC / (runs + 1)};  // + the warm-up
}

}  // namespace

int main(int argc, char** argv) {
  loom::bench::Cli cli("bench_poisson",
                       "PoissonBlend benchmark: first solve (multigrid at several tolerances, exact CHOLMOD, "
                       "OpenCV seamlessClone) and the drag re-solve, errors against the exact solve. Writes "
                       "poisson.csv, poisson_drag.csv and a plot.");
  bool quick = false, disk = false;
  int only = 0;
  std::string inputs_dir;
  std::vector<std::string> modes;
  cli.quick(quick, "one repeat, no 2048² exact solve")
      .option("--size", only, "only N×N regions: 256, 512, 1024 or 2048 (0: all)")
      .flag("--disk", disk, "the region is the disk inscribed in the N×N square (default: the square)")
      .option("--write-inputs", inputs_dir,
              "also write each size's source, target and mask as PNG files into this folder "
              "(source-N.png, target-N.png, mask-N.png: bench_cold runs `loom run` and OpenCV on them)")
      .modes(modes,
             {{"first", "the first solve: multigrid, CHOLMOD and OpenCV, time against error"},
              {"drag", "the drag re-solve (sizes up to 1024)"}},
             "parts to run (default: both)")
      .threads();
  cli.parse(argc, argv);
  const bool drag_only = !loom::bench::wants(modes, "first"), with_drag = loom::bench::wants(modes, "drag");
  const std::string shape = disk ? "disk" : "square";
  loom::bench::Csv csv(disk ? "poisson_disk" : "poisson", {"region", "size", "solver", "tolerance", "seconds", "iterations",
                                   "max_error_255", "rms_error_255", "speedup_vs_opencv",
                                                          "load_average"});
  loom::bench::Csv drag("poisson_drag", {"size", "solver", "start", "tolerance", "seconds_per_resolve",
                                          "cpu_seconds_per_resolve", "fps", "iterations_max",
                                          "max_error_255"});
  const int sizes[] = {256, 512, 1024, 2048};
  const double tolerances[] = {1e-2, 3e-3, 2e-3, 1e-3, 3e-4, 1e-5};
  for (const int N : sizes) {
    if ((only && N != only) || (drag_only && N > 1024)) continue;
    const int runs = quick ? 1 : (N >= 2048 ? 1 : N >= 1024 ? 3 : 5);
    const cv::Size source_size(N + 2, N + 2), target_size(N + 64, N + 64);
    const cv::Mat3b src8 = pattern(source_size, 0.0), dst8 = pattern(target_size, 1.7);
    const cv::Mat source = to_float(src8), target = to_float(dst8);
    cv::Mat1b mask = cv::Mat1b::zeros(source_size);
    if (disk)
      cv::circle(mask, {N / 2, N / 2}, N / 2 - 1, 255, cv::FILLED);  // columns 1 .. N − 1
    else
      mask(cv::Rect(1, 1, N, N)).setTo(255);
    const cv::Point offset(31, 31);
    if (!inputs_dir.empty()) write_inputs(inputs_dir, N, src8, dst8, mask);
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

    if (!drag_only) {
      // OpenCV: the same region, placed by its bounding-box centre.
      cv::Mat3b src_bgr, dst_bgr, out_bgr;
      cv::cvtColor(src8, src_bgr, cv::COLOR_RGB2BGR);
      cv::cvtColor(dst8, dst_bgr, cv::COLOR_RGB2BGR);
      const cv::Rect box = cv::boundingRect(mask);  // OpenCV takes the box's size as max − min
      const cv::Point centre(box.x + offset.x + (box.width - 1) / 2, box.y + offset.y + (box.height - 1) / 2);
      auto opencv_clone = [&] { cv::seamlessClone(src_bgr, dst_bgr, mask, centre, out_bgr, cv::NORMAL_CLONE); };
      opencv_clone();  // its result, for the errors
      cv::Mat3b out_rgb;
      cv::cvtColor(out_bgr, out_rgb, cv::COLOR_BGR2RGB);
      const cv::Mat opencv = to_float(out_rgb)(region.rect);
      const Errors e_cv = run_exact ? compare(opencv, exact, region.unknown) : Errors{NAN, NAN};

      // Each tolerance alternates with OpenCV run by run; the speed-up is the
      // ratio of the medians of those same rounds.
      std::vector<double> opencv_seconds;
      for (const double tol : tolerances) {
        cv::Mat f;
        MultigridPoisson::Result result;
        const auto t = loom::bench::time_alternating(runs, {opencv_clone, [&] {
                                                              f = source_on_rect(region, source, offset);
                                                              MultigridPoisson mg(region.unknown);
                                                              result = mg.solve(poisson_rhs(region, target, source,
                                                                                            offset, Guidance::normal),
                                                                                f, tol, 200);
                                                            }});
        opencv_seconds.push_back(t[0].wall);
        const Errors e = run_exact ? compare(f, exact, region.unknown) : Errors{NAN, NAN};
        csv.row({shape, (long long)N, "multigrid", tol, t[1].wall, (long long)result.iterations, e.max, e.rms,
                 t[0].wall / t[1].wall, loom::bench::load_average()});
      }
      std::sort(opencv_seconds.begin(), opencv_seconds.end());
      const double t_cv = opencv_seconds[opencv_seconds.size() / 2];
      csv.row({shape, (long long)N, "opencv", 0.0, t_cv, 0LL, e_cv.max, e_cv.rms, 1.0, loom::bench::load_average()});
      if (run_exact)
        csv.row({shape, (long long)N, "cholmod", 0.0, exact_seconds, 1LL, 0.0, 0.0, t_cv / exact_seconds,
                 loom::bench::load_average()});
    }

    // Drag: the region moves by a pixel per frame (offsets cycling through
    // x − 1, x, x + 1) and each frame re-solves with the cached hierarchy or
    // factorization; errors are against the exact solve of each frame.
    if (with_drag && N <= 1024 && factor) {
      const cv::Point moves[3] = {{-1, 0}, {0, 0}, {1, 0}};
      cv::Mat frame_exact[3];
      for (int k = 0; k < 3; ++k) {
        const cv::Point moved = offset + moves[k];
        frame_exact[k] = source_on_rect(region, source, moved);
        factor->solve(poisson_rhs(region, target, source, moved, Guidance::normal), frame_exact[k]);
      }
      auto run_drag = [&](const std::string& name, const std::string& start, double tol, auto&& solve) {
        int frame = 0, iterations_max = 0;
        std::vector<cv::Mat> frames;  // compared after the timing
        const WallCpu t = time_wall_cpu(
            [&] {
              const cv::Point moved = offset + moves[frame++ % 3];
              cv::Mat f = source_on_rect(region, source, moved);
              iterations_max = std::max(
                  iterations_max, solve(poisson_rhs(region, target, source, moved, Guidance::normal), f));
              frames.push_back(f);
            },
            9);
        double max_error = 0;
        for (std::size_t k = 0; k < frames.size(); ++k)
          max_error = std::max(max_error, compare(frames[k], frame_exact[k % 3], region.unknown).max);
        drag.row({(long long)N, name, start, tol, t.wall, t.cpu, 1.0 / t.wall, (long long)iterations_max,
                  max_error});
      };
      using Start = MultigridPoisson::Start;
      const MultigridPoisson mg(region.unknown);
      for (const double tol : {1e-4, 2e-3})
        for (const Start start : {Start::guess, Start::previous_correction})
          run_drag("multigrid", start == Start::guess ? "guess" : "previous", tol,
                   [&](const cv::Mat& bb, cv::Mat& f) { return mg.solve(bb, f, tol, 200, start).iterations; });
      run_drag("cholmod", "-", 0.0, [&](const cv::Mat& bb, cv::Mat& f) {
        factor->solve(bb, f);
        return 1;
      });
    }
  }
  if (with_drag) drag.save();
  if (!drag_only) csv.save();
  if (!drag_only) loom::bench::plot(csv, {"seconds", "max_error_255", "size", "PoissonBlend: first-solve time vs max error (1/255 levels)", true, true, ""});
  return 0;
}
