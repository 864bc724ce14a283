// Warp of a 1-megapixel image with 16, 64 and 256 control pairs: megapixels
// per second per method and mode, side by side with OpenCV's thin-plate-spline
// shape transformer on the same pairs, plus a time-vs-error sweep of map_step.
// Reports wall-clock and CPU medians: on a shared machine the wall clock also
// measures the other users, CPU seconds / cores bounds what an idle machine gives.
//
//   build/bin/bench_warp [--quick] [--cpu-hogs N] [--memory-hogs N]
//
// With hogs, N processes of its own load the machine while it measures (busy
// loops, or copies between two 256-MB buffers, which fight for the caches
// and memory bandwidth as builds do), so the ratio to OpenCV can be read under
// a known load; they are stopped by PID at the end.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <ctime>
#include <iostream>
#include <random>
#include <thread>

#include <sys/wait.h>
#include <unistd.h>

#include <opencv2/imgproc.hpp>
#include <opencv2/shape/shape_transformer.hpp>

#include "bench_harness.hpp"
#include "control_points.hpp"
#include "generators.hpp"
#include "idw.hpp"
#include "rbf.hpp"
#include "warp_image.hpp"

using namespace loom::warp;

namespace {

constexpr int kSide = 1024;  // 1 Mpx

// The Checkerboard node's default colours, cells of 64 pixels.
cv::Mat checkerboard() {
  return loom::generate::checkerboard(loom::Vec2i(kSide, kSide), kSide / 64, loom::Color{{0.95, 0.95, 0.95, 1}},
                                      loom::Color{{0.15, 0.3, 0.6, 1}});
}

// Smooth, so that differences between two warps measure their maps, not edges.
cv::Mat smooth_image() {
  cv::Mat m(kSide, kSide, CV_32FC1);
  for (int i = 0; i < kSide; ++i)
    for (int j = 0; j < kSide; ++j) m.at<float>(i, j) = float(0.5 + 0.4 * std::sin(j / 40.0) * std::cos(i / 55.0));
  return m;
}

void random_pairs(int n, unsigned seed, Eigen::MatrixX2d& P, Eigen::MatrixX2d& Q) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(32, kSide - 32), d(-30, 30);
  P.resize(n, 2);
  Q.resize(n, 2);
  for (int i = 0; i < n; ++i) {
    P.row(i) << u(rng), u(rng);
    Q.row(i) = P.row(i) + Eigen::RowVector2d(d(rng), d(rng));
  }
}

// Fits the map of `method` on A → B, cleaned as the node does.
RowMap fit(const std::string& method, const Eigen::MatrixX2d& A, const Eigen::MatrixX2d& B) {
  const ControlPoints cp = clean_control_points(A, B, 1e-3, nullptr);
  if (method == "idw") {
    auto m = std::make_shared<const IdwMap>(fit_idw(cp.p, cp.q, 2, true));
    return [m](double y, const double* x, int k, double* fx, double* fy) { evaluate_idw_row(*m, y, x, k, fx, fy); };
  }
  const RbfKernel kernel = method == "rbf_tps" ? RbfKernel::thin_plate : RbfKernel::multiquadric;
  auto m = std::make_shared<const RbfMap>(fit_rbf(cp.p, cp.q, kernel, 1, 0, nullptr));
  return [m](double y, const double* x, int k, double* fx, double* fy) { evaluate_rbf_row(*m, y, x, k, fx, fy); };
}

// What ImageWarp does: fit (inverse mode: on the swapped pairs) and warp.
cv::Mat warp(const std::string& method, const std::string& mode, const cv::Mat& src, const Eigen::MatrixX2d& P,
             const Eigen::MatrixX2d& Q) {
  const cv::Scalar white(1, 1, 1, 1);
  if (mode == "inverse") return inverse_warp(src, fit(method, Q, P), src.size(), 1, Outside::background, white, {});
  Splat s = forward_warp(src, fit(method, P, Q), src.size(), 1, white, {});
  if (mode == "forward_fill") fill_cracks(s.image, s.written, std::clamp(int(std::ceil(s.max_stretch)), 1, 16));
  return s.image;
}

// OpenCV's thin-plate spline: warpImage samples the source at the map fitted
// from the second shape to the first, so the target points go first. OpenCV
// puts pixel centers at integers, Loom at +0.5: the points move by −0.5.
cv::Mat opencv_tps(const cv::Mat& src, const Eigen::MatrixX2d& P, const Eigen::MatrixX2d& Q) {
  std::vector<cv::Point2f> p, q;
  std::vector<cv::DMatch> matches;
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    p.emplace_back(float(P(i, 0) - 0.5), float(P(i, 1) - 0.5));
    q.emplace_back(float(Q(i, 0) - 0.5), float(Q(i, 1) - 0.5));
    matches.emplace_back(int(i), int(i), 0.0f);
  }
  cv::Ptr<cv::ThinPlateSplineShapeTransformer> tps = cv::createThinPlateSplineShapeTransformer(0);
  tps->estimateTransformation(cv::Mat(q).reshape(2, 1), cv::Mat(p).reshape(2, 1), matches);
  cv::Mat out;
  tps->warpImage(src, out, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar::all(1));
  return out;
}

struct Measured {
  double wall = 0, cpu = 0;  // medians, seconds
};

template <class F>
Measured measure(F&& f, int runs) {
  std::vector<double> cpu;
  const loom::bench::Timing t = loom::bench::time_median([&] {
    const std::clock_t start = std::clock();
    f();
    cpu.push_back(double(std::clock() - start) / CLOCKS_PER_SEC);
  }, runs);
  cpu.erase(cpu.begin());  // the warm-up
  std::sort(cpu.begin(), cpu.end());
  return {t.median, cpu[cpu.size() / 2]};
}

// Largest distance in pixels between the map on a map_step lattice
// (interpolated) and the exact map, over every pixel.
double map_step_error(const RowMap& f, int step) {
  const cv::Size size(kSide, kSide);
  cv::Mat exact(size, CV_64FC2), coarse(size, CV_64FC2);
  auto store = [](cv::Mat& m) {
    return [&m](int i, const double* fx, const double* fy) {
      for (int j = 0; j < m.cols; ++j) m.at<cv::Vec2d>(i, j) = cv::Vec2d(fx[j], fy[j]);
    };
  };
  map_rows(f, size, 1, store(exact), {});
  map_rows(f, size, step, store(coarse), {});
  return cv::norm(exact, coarse, cv::NORM_INF);
}

// Processes that load the machine while they live: busy loops, or copies
// between two 256-MB buffers.
class Hogs {
 public:
  Hogs(int cpu, int memory) {
    for (int k = 0; k < cpu + memory; ++k) {
      const pid_t pid = ::fork();
      if (pid == 0) k < cpu ? spin() : copy();
      if (pid > 0) pids_.push_back(pid);
    }
    if (!pids_.empty()) std::this_thread::sleep_for(std::chrono::seconds(3));  // the buffers touched, the load risen
  }
  ~Hogs() {
    for (pid_t pid : pids_) ::kill(pid, SIGKILL);
    for (pid_t pid : pids_) ::waitpid(pid, nullptr, 0);
  }
  Hogs(const Hogs&) = delete;
  Hogs& operator=(const Hogs&) = delete;

 private:
  [[noreturn]] static void spin() {
    for (volatile unsigned long n = 0;; n = n + 1) {
    }
  }
  [[noreturn]] static void copy() {
    const std::size_t bytes = std::size_t(256) << 20;
    std::vector<char> a(bytes, 1), b(bytes, 2);
    for (;;) {
      std::memcpy(b.data(), a.data(), bytes);
      std::memcpy(a.data(), b.data(), bytes);
    }
  }
  std::vector<pid_t> pids_;
};

}  // namespace

int main(int argc, char** argv) {
  loom::bench::Cli cli("bench_warp",
                       "ImageWarp (IDW, RBF, thin-plate; inverse, forward, forward+fill) on a 1 Mpx image with 16, "
                       "64 and 256 pairs, side by side with OpenCV's thin-plate-spline shape transformer; and "
                       "map_step time against map error.");
  bool quick = false;
  int cpu_hogs = 0, memory_hogs = 0;
  cli.quick(quick, "64 pairs, 3 runs")
      .threads()
      .option("--cpu-hogs", cpu_hogs, "processes of busy loops that load the machine while it measures")
      .option("--memory-hogs", memory_hogs, "processes copying 256-MB buffers while it measures");
  cli.parse(argc, argv);
  const Hogs hogs(std::max(0, cpu_hogs), std::max(0, memory_hogs));
  std::cout << "load average " << loom::bench::load_average() << " (" << cpu_hogs << " busy-loop and " << memory_hogs
            << " memory-copy processes of the benchmark's own)\n";
  const bool loaded = cpu_hogs > 0 || memory_hogs > 0;
  const int runs = quick ? 3 : 7;
  const std::vector<int> counts = quick ? std::vector<int>{64} : std::vector<int>{16, 64, 256};
  const cv::Mat board = checkerboard(), smooth = smooth_image();
  const double mpx = double(kSide) * kSide / 1e6;

  // gnuplot reads _ as a subscript: series names use - and +.
  auto label = [](std::string s) {
    std::replace(s.begin(), s.end(), '_', '-');
    return s;
  };
  loom::bench::Csv csv(loaded ? "warp_loaded" : "warp",
                       {"series", "pairs", "seconds", "cpu_seconds", "mpx_per_s", "mpx_per_cpu_s",
                        "speedup_vs_opencv_tps", "cpu_speedup_vs_opencv_tps"});
  for (int n : counts) {
    Eigen::MatrixX2d P, Q;
    random_pairs(n, 7, P, Q);
    const Measured cv_time = measure([&] { opencv_tps(board, P, Q); }, quick ? 1 : 3);
    csv.row({"opencv-tps inverse", (long long)n, cv_time.wall, cv_time.cpu, mpx / cv_time.wall, mpx / cv_time.cpu,
             1.0, 1.0});
    for (const std::string method : {"idw", "rbf", "rbf_tps"})
      for (const std::string mode : {"inverse", "forward", "forward_fill"}) {
        const Measured t = measure([&] { warp(method, mode, board, P, Q); }, runs);
        csv.row({label(method + " " + mode), (long long)n, t.wall, t.cpu, mpx / t.wall, mpx / t.cpu,
                 cv_time.wall / t.wall, cv_time.cpu / t.cpu});
      }
    const cv::Mat ours = warp("rbf_tps", "inverse", smooth, P, Q), theirs = opencv_tps(smooth, P, Q);
    const cv::Rect inner(64, 64, kSide - 128, kSide - 128);
    std::cout << "pairs " << n << ": Loom thin_plate vs OpenCV TPS on a smooth image in [0.1, 0.9]: max |diff| "
              << cv::norm(ours(inner), theirs(inner), cv::NORM_INF) << ", mean |diff| "
              << cv::norm(ours(inner), theirs(inner), cv::NORM_L1) / inner.area() << "\n";
  }
  csv.save();
  loom::bench::plot(csv, {"pairs", "mpx_per_s", "series", "1 Mpx warp: Mpx per second (wall clock)", true, true, ""});
  loom::bench::plot(csv, {"pairs", "mpx_per_cpu_s", "series", "1 Mpx warp: Mpx per CPU-second (all threads)", true, true,
                          "_cpu"});

  if (loaded) return 0;  // the map_step sweep is measured on a quiet machine

  loom::bench::Csv sweep("warp_map_step", {"method", "map_step", "seconds", "cpu_seconds", "max_map_error_px"});
  Eigen::MatrixX2d P, Q;
  random_pairs(64, 9, P, Q);
  for (const std::string method : {"idw", "rbf"}) {
    const RowMap f = fit(method, Q, P);
    for (int step : {1, 2, 4, 8, 16, 32}) {
      const Measured t = measure([&] {
        inverse_warp(board, f, board.size(), step, Outside::background, cv::Scalar::all(1), {});
      }, runs);
      sweep.row({method, (long long)step, t.wall, t.cpu, map_step_error(f, step)});
    }
  }
  sweep.save();
  loom::bench::plot(sweep, {"cpu_seconds", "max_map_error_px", "method",
                            "map_step: CPU time vs map error (64 pairs, 1 Mpx)", true, true, "_time_error"});
  return 0;
}
