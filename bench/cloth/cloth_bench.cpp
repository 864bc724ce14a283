// Mass-spring cloth: implicit Euler by Newton against Liu et al. 2013's
// local/global iteration (plain and with Wang 2015's Chebyshev acceleration).
//
//  cloth_frame:   one frame (h = 1/30) of an 81×81 curtain (k = 1e5, top edge
//                 pinned, in gusty wind, already swinging): time per frame
//                 against the error of the step, relative to a Newton run
//                 converged to 1e-13 with the same h. Local/global at 1..200
//                 iterations, Newton at 1..10.
//  cloth_frames100: the same on a 41×41 curtain over 100 frames: position
//                 error after 100 frames against the converged-Newton
//                 trajectory, and that trajectory's own error against one with
//                 10× smaller h (the time-discretization error both share).
//  cloth_scaling: 41², 81², 161², 321²: factorization time, local/global
//                 frame time (10 iterations), resident memory the factored
//                 solver adds; Newton iteration time up to 161².
//
// Error: ‖x − x_ref‖ / ‖x_ref − x_n‖, relative to how far the step moves the
// cloth (‖x − x_ref‖/‖x_ref‖ is also written). --quick: fewer sizes and runs.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "bench_harness.hpp"
#include "time_step.hpp"

namespace {

using namespace loom::cloth;
using Clock = std::chrono::steady_clock;

SpringSystem curtain(int n) {
  SpringSystem s = grid_cloth(n, n, Eigen::Vector3d(-0.5, 0.5, 0), Eigen::Vector3d(1, 0, 0),
                              Eigen::Vector3d(0, 1, 0), 0.1, 1e5, 1e5, 1e5);
  fix_vertices(s, {}, Eigen::Vector3d(-1, 1.49, -1), Eigen::Vector3d(1, 2, 1));
  return s;
}

StepSettings windy(Solver solver, int iterations, double tolerance = 0, bool chebyshev = false) {
  StepSettings st;
  st.solver = solver;
  st.solve.iterations = iterations;
  st.solve.tolerance = tolerance;
  st.solve.record_residuals = false;
  st.solve.chebyshev = chebyshev;
  st.wind_speed = 6;
  st.turbulence = 0.8;
  st.damping = 0.5;
  return st;
}

StepSettings reference_settings() { return windy(Solver::newton, 100, 1e-13); }

long resident_kb() {
  std::ifstream f("/proc/self/statm");
  long pages = 0, resident = 0;
  f >> pages >> resident;
  return resident * 4;
}

std::string load() {
  std::ifstream f("/proc/loadavg");
  std::string a;
  f >> a;
  return a;
}

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

void frame_study(int n, int runs) {
  const double h = 1.0 / 30;
  auto system = std::make_shared<const SpringSystem>(curtain(n));
  const auto t0 = Clock::now();
  const LocalGlobalSolver lg(*system, h);
  const double factor_seconds = seconds_since(t0);
  // Swing it first: 20 frames of converged Newton.
  ClothState state = rest_state(system);
  for (int f = 0; f < 20; ++f) state = step(state, h, reference_settings(), nullptr).state;
  const Eigen::MatrixX3d ref = step(state, h, reference_settings(), nullptr).state.x;
  const double moved = (ref - state.x).norm();

  loom::bench::Csv csv("cloth_frame", {"method", "iterations", "seconds", "error", "error_vs_x", "load"});
  auto measure = [&](const std::string& method, int iterations, const StepSettings& st) {
    Eigen::MatrixX3d x;
    const auto t = loom::bench::time_median([&] { x = step(state, h, st, &lg).state.x; }, runs);
    const double err = (x - ref).norm();
    csv.row({method, static_cast<long long>(iterations), t.median, err / moved, err / ref.norm(), load()});
    return std::make_pair(t.median, err / moved);
  };
  std::vector<std::pair<double, double>> lg_plain, newton;
  for (int it : {1, 2, 5, 10, 20, 50, 100, 200}) {
    lg_plain.push_back(measure("local_global", it, windy(Solver::local_global, it)));
    measure("local_global_chebyshev", it, windy(Solver::local_global, it, 0, true));
  }
  for (int it = 1; it <= 10; ++it) newton.push_back(measure("newton", it, windy(Solver::newton, it)));
  csv.save();
  loom::bench::plot(csv, {"seconds", "error", "method", "curtain, one frame (h = 1/30): step error vs time", true, true, ""});

  // The target: local/global at 10 iterations against the fastest Newton
  // that is at least as accurate.
  const auto lg10 = lg_plain[3];
  double newton_time = -1;
  int newton_iterations = 0;
  for (size_t k = 0; k < newton.size(); ++k)
    if (newton[k].second <= lg10.second) {
      newton_time = newton[k].first;
      newton_iterations = static_cast<int>(k + 1);
      break;
    }
  std::printf("\n%dx%d curtain: factorization %.1f ms; local/global 10 iterations %.2f ms/frame, error %.3g; ",
              n, n, 1e3 * factor_seconds, 1e3 * lg10.first, lg10.second);
  if (newton_time > 0)
    std::printf("Newton reaches that error in %d iteration(s), %.1f ms/frame: %.1fx slower (load %s)\n",
                newton_iterations, 1e3 * newton_time, newton_time / lg10.first, load().c_str());
  else
    std::printf("no Newton run up to 10 iterations is as accurate (load %s)\n", load().c_str());
}

void trajectory_study(int n, int frames) {
  const double h = 1.0 / 30;
  auto system = std::make_shared<const SpringSystem>(curtain(n));
  const LocalGlobalSolver lg(*system, h);
  auto run = [&](const StepSettings& st, int substeps, const LocalGlobalSolver* solver, double* seconds) {
    ClothState s = rest_state(system);
    const auto t0 = Clock::now();
    for (int f = 0; f < frames; ++f)
      for (int k = 0; k < substeps; ++k) s = step(s, h / substeps, st, solver).state;
    if (seconds) *seconds = seconds_since(t0) / frames;
    return s.x;
  };
  double t_ref = 0;
  const Eigen::MatrixX3d ref = run(reference_settings(), 1, nullptr, &t_ref);
  const Eigen::MatrixX3d ref_fine = run(reference_settings(), 10, nullptr, nullptr);
  const double scale = (ref - system->X).norm();
  loom::bench::Csv csv("cloth_frames100", {"method", "iterations", "seconds_per_frame", "error", "load"});
  csv.row({std::string("newton_converged_vs_h/10"), 100LL, t_ref, (ref - ref_fine).norm() / scale, load()});
  for (int it : {1, 2, 5, 10, 20, 50, 100, 200})
    for (bool cheb : {false, true}) {
      double t = 0;
      const Eigen::MatrixX3d x = run(windy(Solver::local_global, it, 0, cheb), 1, &lg, &t);
      csv.row({std::string(cheb ? "local_global_chebyshev" : "local_global"), static_cast<long long>(it), t,
               (x - ref).norm() / scale, load()});
    }
  for (int it : {1, 2, 3, 5, 10}) {
    double t = 0;
    const Eigen::MatrixX3d x = run(windy(Solver::newton, it), 1, nullptr, &t);
    csv.row({std::string("newton"), static_cast<long long>(it), t, (x - ref).norm() / scale, load()});
  }
  csv.save();
  loom::bench::plot(csv, {"seconds_per_frame", "error", "method",
                          "curtain, 100 frames: position error vs time per frame", true, true, ""});
}

void scaling_study(const std::vector<int>& sizes, int runs) {
  const double h = 1.0 / 30;
  loom::bench::Csv csv("cloth_scaling", {"vertices", "springs", "factor_seconds", "lg10_seconds",
                                         "newton_iteration_seconds", "factor_mb", "load"});
  for (int n : sizes) {
    auto system = std::make_shared<const SpringSystem>(curtain(n));
    const long before = resident_kb();
    const auto t0 = Clock::now();
    auto lg = std::make_unique<LocalGlobalSolver>(*system, h);
    const double factor = seconds_since(t0);
    const long after = resident_kb();
    ClothState state = rest_state(system);
    const auto t = loom::bench::time_median([&] { step(state, h, windy(Solver::local_global, 10), lg.get()); }, runs);
    double newton = -1;
    if (n <= 161)
      newton = loom::bench::time_median([&] { step(state, h, windy(Solver::newton, 1), nullptr); }, 3).median;
    csv.row({static_cast<long long>(n * n), static_cast<long long>(system->spring_count()), factor, t.median,
             newton, (after - before) / 1024.0, load()});
  }
  csv.save();
  loom::bench::plot(csv, {"vertices", "lg10_seconds", "", "local/global frame time (10 iterations) vs size", true, true,
                          "_frame"});
}

}  // namespace

int main(int argc, char** argv) {
  loom::bench::handle_help(argc, argv,
                           "bench_cloth [--quick]: Newton vs local/global (plain, Chebyshev) on pinned "
                           "curtains; writes cloth_frame, cloth_frames100, cloth_scaling CSV and plots");
  const bool quick = argc > 1 && std::string(argv[1]) == "--quick";
  std::printf("load at start: %s\n", load().c_str());
  frame_study(quick ? 41 : 81, quick ? 3 : 7);
  trajectory_study(quick ? 21 : 41, 100);
  scaling_study(quick ? std::vector<int>{41, 81} : std::vector<int>{41, 81, 161, 321}, quick ? 3 : 5);
  std::printf("load at end: %s\n", load().c_str());
  return 0;
}
