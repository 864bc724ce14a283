// Mass-spring cloth: implicit Euler by Newton against Liu et al. 2013's
// local/global iteration (plain, with Wang 2015's Chebyshev acceleration, and
// with Peng et al. 2018's Anderson acceleration).
//
//  cloth_frame:   one frame (h = 1/30) of an 81×81 curtain (k = 1e5, top edge
//                 pinned, in gusty wind, already swinging): time per frame
//                 against the error of the step, relative to a Newton run
//                 converged to 1e-10 with the same h. Local/global at 1..200
//                 iterations, Newton at 1..10.
//  cloth_frames100: a 25×25 curtain held at its top corners, pushed at
//                 1 m/s out of its plane, over 100 frames: RMS position error (m) after 100
//                 frames against the converged-Newton trajectory, and that
//                 trajectory's own error against one with 10× smaller h (the
//                 time-discretization error both share).
//  cloth_convergence: local/global residual per iteration (plain, Chebyshev)
//                 on the 81² curtain at 0.1, 10 and 1000 kg/m².
//  cloth_start:   where local/global starts each step: distance from the
//                 equilibrium at rest, error in motion, cost per frame.
//  cloth_scaling: 41², 81², 161², 321²: factorization time, local/global
//                 frame time (10 iterations), resident memory the factored
//                 solver adds; Newton iteration CPU time up to 81².
//  cloth_cuboid:  the assignment's cuboid (5×5×5, 0.5 m, 1000 kg/m³) dropped
//                 from 0.3 m onto the ground with k = 1e3, 1e4, 1e5: its height
//                 over time relative to the rest height (Newton, 4 substeps).
//  cloth_accuracy: one step's ‖∇E‖ / ‖∇E(y)‖ against time, per iteration,
//                 for plain, Chebyshev, Anderson and Newton on the light and
//                 heavy 81² curtains and the drape (see accuracy_study).
//  cloth_accuracy_frames: the time to 1e-6 of that measure at frames 10-40
//                 of the light curtain (see accuracy_over_frames).
// Curtains are 1 m wide, k = 1e5 for every class, 0.1 kg/m² (--density D:
// D kg/m², CSV names suffixed _densityD).
// Run with OPENBLAS_NUM_THREADS=1 on a shared machine: CPU time then counts no
// spinning BLAS threads.
//
// Error: ‖x − x_ref‖ / ‖x_ref − x_n‖, relative to how far the step moves the
// cloth (‖x − x_ref‖/‖x_ref‖ is also written). --quick: fewer sizes and runs.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bench_harness.hpp"
#include "incremental_potential.hpp"
#include "loom/process_start.hpp"
#include "time_step.hpp"

namespace {

using namespace loom::cloth;
using Clock = std::chrono::steady_clock;

// kg/m²; --density changes it (and the CSV names get a suffix).
double g_density = 0.1;
std::string g_suffix;

SpringSystem curtain(int n) {
  SpringSystem s = grid_cloth(n, n, Eigen::Vector3d(-0.5, 0.5, 0), Eigen::Vector3d(1, 0, 0),
                              Eigen::Vector3d(0, 1, 0), g_density, 1e5, 1e5, 1e5);
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

// Newton to the roundoff floor of the gradient: tolerance 1e-13 is below
// what the light curtain reaches, so it stops when the line search finds no
// decrease of E any more (a minimizer to rounding). Its convergence is linear
// where springs are compressed: the light curtain needs a few hundred
// iterations, a heavy one about 15.
StepSettings reference_settings() { return windy(Solver::newton, 2000, 1e-13); }

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

struct WallCpu {
  double wall, cpu;  // medians, seconds; cpu is the process's (every thread)
};

// One warm-up run, then the medians of `runs` runs of wall and CPU time.
template <class F>
WallCpu time_wall_cpu(F&& f, int runs) {
  f();
  std::vector<double> wall, cpu;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = Clock::now();
    const std::clock_t c0 = std::clock();
    f();
    cpu.push_back(static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
    wall.push_back(seconds_since(t0));
  }
  std::sort(wall.begin(), wall.end());
  std::sort(cpu.begin(), cpu.end());
  return {wall[wall.size() / 2], cpu[cpu.size() / 2]};
}

void frame_study(int n, int runs) {
  const double h = 1.0 / 30;
  auto system = std::make_shared<const SpringSystem>(curtain(n));
  const auto t0 = Clock::now();
  const LocalGlobalSolver lg(*system, h);
  const double factor_seconds = seconds_since(t0);
  // Swing it first: 20 frames of local/global with 100 iterations.
  ClothState state = rest_state(system);
  for (int f = 0; f < 20; ++f) state = step(state, h, windy(Solver::local_global, 100), &lg).state;
  // Newton keeps its symbolic analysis across calls (as the node does across
  // substeps): a timed Newton iteration is assembly, numeric factorization,
  // solve and line search.
  loom::cloth::NewtonWorkspace newton_workspace;
  const StepResult reference = step(state, h, reference_settings(), nullptr, &newton_workspace);
  const Eigen::MatrixX3d& ref = reference.state.x;
  const double moved = (ref - state.x).norm();
  std::printf("%dx%d curtain, %g kg/m^2 (%.3g kg per vertex, h^2 k / m = %.3g): reference Newton %d iterations, "
              "relative gradient %.2g\n",
              n, n, g_density, system->mass.maxCoeff(), h * h * 1e5 / system->mass.maxCoeff(),
              reference.report.iterations, reference.report.residuals.back());

  loom::bench::Csv csv("cloth_frame" + g_suffix,
                       {"method", "iterations", "seconds", "cpu_seconds", "error", "error_vs_x", "load"});
  struct Point {
    double wall, cpu, error;
  };
  auto measure = [&](const std::string& method, int iterations, const StepSettings& st) {
    Eigen::MatrixX3d x;
    // Long runs (a second or more each): one timed run is enough.
    const bool is_long = st.solver == Solver::newton ? iterations > 10 : iterations > 200;
    const WallCpu t =
        time_wall_cpu([&] { x = step(state, h, st, &lg, &newton_workspace).state.x; }, is_long ? 1 : runs);
    const double err = (x - ref).norm();
    csv.row({method, static_cast<long long>(iterations), t.wall, t.cpu, err / moved, err / ref.norm(), load()});
    return Point{t.wall, t.cpu, err / moved};
  };
  std::vector<Point> lg_plain, newton;
  for (int it : {1, 2, 5, 10, 20, 50, 100, 200, 1000, 5000}) {
    lg_plain.push_back(measure("local_global", it, windy(Solver::local_global, it)));
    measure("local_global_chebyshev", it, windy(Solver::local_global, it, 0, true));
  }
  for (int it : {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 15, 20, 30, 50})
    newton.push_back(measure("newton", it, windy(Solver::newton, it)));
  csv.save();
  loom::bench::plot(csv, {"seconds", "error", "method", "curtain, one frame (h = 1/30): step error vs time", true, true, ""});
  loom::bench::plot(csv, {"cpu_seconds", "error", "method", "curtain, one frame (h = 1/30): step error vs CPU time", true,
                          true, "_cpu"});

  // The target: local/global at 10 iterations against the fastest Newton
  // that is at least as accurate.
  const Point lg10 = lg_plain[3];
  const Point* match = nullptr;
  for (const auto& p : newton)
    if (p.error <= lg10.error) {
      match = &p;
      break;
    }
  std::printf("\n%dx%d curtain: factorization %.1f ms; local/global 10 iterations %.2f ms/frame wall, %.2f ms CPU, "
              "error %.3g; ",
              n, n, 1e3 * factor_seconds, 1e3 * lg10.wall, 1e3 * lg10.cpu, lg10.error);
  static const int newton_iterations[] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 15, 20, 30, 50};
  if (match)
    std::printf("Newton reaches that error in %d iteration(s), %.1f ms wall, %.1f ms CPU: %.1fx (wall), %.1fx (CPU) "
                "slower (load %s)\n",
                newton_iterations[match - newton.data()], 1e3 * match->wall, 1e3 * match->cpu,
                match->wall / lg10.wall, match->cpu / lg10.cpu, load().c_str());
  else
    std::printf("no Newton run up to 50 iterations is as accurate (load %s)\n", load().c_str());
  std::printf("one Newton iteration %.1f ms wall, %.1f ms CPU = %.1fx (wall), %.1fx (CPU) local/global's 10\n",
              1e3 * newton[0].wall, 1e3 * newton[0].cpu, newton[0].wall / lg10.wall, newton[0].cpu / lg10.cpu);
}

// A curtain held by its two top corners only, pushed out of its plane at
// 1 m/s: it sags and swings (no wind, so nearby trajectories stay nearby; no
// damping).
void trajectory_study(int n, int frames) {
  const double h = 1.0 / 30;
  SpringSystem corners = grid_cloth(n, n, Eigen::Vector3d(-0.5, 0.5, 0), Eigen::Vector3d(1, 0, 0),
                                    Eigen::Vector3d(0, 1, 0), g_density, 1e5, 1e5, 1e5);
  corners.fixed[grid_index(n, 0, n - 1)] = corners.fixed[grid_index(n, n - 1, n - 1)] = 1;
  auto system = std::make_shared<const SpringSystem>(corners);
  // No wind and no damping: with damping it settles to the same rest shape
  // whatever h, and the comparison says nothing after 100 frames.
  auto calm = [](StepSettings st) {
    st.wind_speed = 0;
    st.damping = 0;
    return st;
  };
  const LocalGlobalSolver lg(*system, h);
  auto run = [&](const StepSettings& st, int substeps, const LocalGlobalSolver* solver, double* seconds) {
    loom::cloth::NewtonWorkspace newton_workspace;
    ClothState s = rest_state(system);
    // A push out of its plane: it swings about the line through the corners.
    for (int i = 0; i < s.v.rows(); ++i)
      if (!system->fixed[i]) s.v(i, 2) = 1;
    const auto t0 = Clock::now();
    for (int f = 0; f < frames; ++f)
      for (int k = 0; k < substeps; ++k) s = step(s, h / substeps, st, solver, &newton_workspace).state;
    if (seconds) *seconds = seconds_since(t0) / frames;
    return s.x;
  };
  double t_ref = 0;
  const Eigen::MatrixX3d ref = run(calm(reference_settings()), 1, nullptr, &t_ref);
  const Eigen::MatrixX3d ref_fine = run(calm(reference_settings()), 10, nullptr, nullptr);
  const double rms = 1 / std::sqrt(static_cast<double>(system->vertices()));  // error in meters per vertex
  loom::bench::Csv csv("cloth_frames100" + g_suffix,
                       {"method", "iterations", "seconds_per_frame", "rms_error_m", "load"});
  csv.row({std::string("newton_converged_vs_h/10"), 400LL, t_ref, (ref - ref_fine).norm() * rms, load()});
  for (int it : {1, 2, 5, 10, 20, 50, 100, 200})
    for (bool cheb : {false, true}) {
      double t = 0;
      const Eigen::MatrixX3d x = run(calm(windy(Solver::local_global, it, 0, cheb)), 1, &lg, &t);
      csv.row({std::string(cheb ? "local_global_chebyshev" : "local_global"), static_cast<long long>(it), t,
               (x - ref).norm() * rms, load()});
    }
  for (int it : {1, 2, 3, 5, 10}) {
    double t = 0;
    const Eigen::MatrixX3d x = run(calm(windy(Solver::newton, it)), 1, nullptr, &t);
    csv.row({std::string("newton"), static_cast<long long>(it), t, (x - ref).norm() * rms, load()});
  }
  csv.save();
  loom::bench::plot(csv, {"seconds_per_frame", "rms_error_m", "method",
                          "curtain held at two corners, 100 frames: position error vs time per frame", true, true, ""});
}

void scaling_study(const std::vector<int>& sizes, int runs) {
  const double h = 1.0 / 30;
  loom::bench::Csv csv("cloth_scaling" + g_suffix, {"vertices", "springs", "factor_seconds", "lg10_seconds", "lg10_cpu_seconds",
                                         "newton_iteration_cpu_seconds", "factor_mb", "load"});
  for (int n : sizes) {
    auto system = std::make_shared<const SpringSystem>(curtain(n));
    const long before = resident_kb();
    const auto t0 = Clock::now();
    auto lg = std::make_unique<LocalGlobalSolver>(*system, h);
    const double factor = seconds_since(t0);
    const long after = resident_kb();
    ClothState state = rest_state(system);
    const WallCpu t = time_wall_cpu([&] { step(state, h, windy(Solver::local_global, 10), lg.get()); }, runs);
    double newton = -1;
    loom::cloth::NewtonWorkspace newton_workspace;
    if (n <= 81)
      newton = time_wall_cpu([&] { step(state, h, windy(Solver::newton, 1), nullptr, &newton_workspace); }, 3).cpu;
    csv.row({static_cast<long long>(n * n), static_cast<long long>(system->spring_count()), factor, t.wall, t.cpu,
             newton, (after - before) / 1024.0, load()});
  }
  csv.save();
  loom::bench::plot(csv, {"vertices", "lg10_seconds", "", "local/global frame time (10 iterations) vs size", true, true,
                          "_frame"});
}

// Residual ‖∇E(x_k)‖/‖∇E(x_0)‖ per local/global iteration, plain and with
// Chebyshev (ρ = 0.99, 0.999), on the swinging 81² curtain at three
// densities: h² k / m sets how quasi-static a step is, and with it how close
// to 1 the plain iteration's convergence factor gets. The factor over
// iterations 100..200 is printed.
void convergence_study(int n) {
  const double h = 1.0 / 30;
  loom::bench::Csv csv("cloth_convergence", {"curve", "iteration", "residual", "load"});
  const double saved = g_density;
  for (double density : {0.1, 10.0, 1000.0}) {
    g_density = density;
    auto system = std::make_shared<const SpringSystem>(curtain(n));
    const LocalGlobalSolver lg(*system, h);
    ClothState state = rest_state(system);
    for (int f = 0; f < 20; ++f) state = step(state, h, windy(Solver::local_global, 100), &lg).state;
    const double ratio = h * h * 1e5 / system->mass.maxCoeff();
    for (double rho : {0.0, 0.99, 0.999}) {
      StepSettings st = windy(Solver::local_global, 200, 0, rho > 0);
      st.solve.record_residuals = true;
      if (rho > 0) st.solve.chebyshev_rho = rho;
      const StepResult r = step(state, h, st, &lg);
      char name[96];
      std::snprintf(name, sizeof name, "%g kg/m2 (h2k/m %.2g) %s", density, ratio,
                    rho > 0 ? (rho == 0.99 ? "chebyshev 0.99" : "chebyshev 0.999") : "plain");
      for (std::size_t k = 0; k < r.report.residuals.size(); ++k)
        csv.row({std::string(name), static_cast<long long>(k + 1), r.report.residuals[k], load()});
      const auto& res = r.report.residuals;
      std::printf("%-40s residual after 10: %.3g, 30: %.3g, 200: %.3g; factor per iteration (100..200) %.5f\n", name,
                  res[9], res[29], res[199], std::pow(res[199] / res[99], 1.0 / 100));
    }
  }
  g_density = saved;
  csv.save();
  loom::bench::plot(csv, {"iteration", "residual", "curve", "81x81 curtain: local/global residual per iteration", false,
                          true, ""});
}

void cuboid_study() {
  const double h = 1.0 / 120;
  loom::bench::Csv csv("cloth_cuboid", {"k", "seconds", "height_ratio", "load"});
  for (double k : {1e3, 1e4, 1e5}) {
    auto system = std::make_shared<const SpringSystem>(
        cuboid_lattice(5, 5, 5, Eigen::Vector3d(-0.25, 0.3, -0.25), Eigen::Vector3d(0.25, 0.8, 0.25), 1000, k, k, k));
    StepSettings st;
    st.solver = Solver::newton;
    st.solve.iterations = 50;
    st.solve.tolerance = 1e-8;
    st.ground = true;
    ClothState state = rest_state(system);
    for (int n = 0; n <= 4 * 90; ++n) {
      if (n % 4 == 0)
        csv.row({std::string("k = ") + (k == 1e3 ? "1e3" : k == 1e4 ? "1e4" : "1e5"), state.time,
                 (state.x.col(1).maxCoeff() - state.x.col(1).minCoeff()) / 0.5, load()});
      state = step(state, h, st, nullptr).state;
    }
  }
  csv.save();
  loom::bench::plot(csv, {"seconds", "height_ratio", "k", "cuboid dropped on the ground: height / rest height", false,
                          false, ""});
}

// Time to accuracy: one step's ‖∇E‖ against the time spent, per iteration,
// for plain local/global, Chebyshev (ρ = 0.99 and 0.999), Anderson (window
// 6, energy safeguard) and Newton, on three scenes: the light 81² curtain
// (0.1 kg/m²) and the heavy one (6400 kg/m², about 1 kg per vertex),
// swinging in wind, and the drape (31², k = 1e4, 1 kg/m², on a sphere and
// the ground with friction 0.5, 30 frames in: in contact). Each method
// starts where the node starts it (Newton from the prediction y,
// local/global from the lower-E start), and the light curtain is run once
// more with every method from y. One scale for all: ‖∇E(x_k)‖ / ‖∇E(y)‖.
// (The solvers report ‖∇E‖ relative to their own start, which on the light
// curtain differ by 5 orders of magnitude; that column is written too.)
// Each curve is the median, per iteration, of `runs` runs' timestamps (the
// iterates are the same in every run). The drape's residual measures the
// springs' E only (docs/cloth.md: with contacts it does not reach zero), and
// Newton's there is relative to each of its two passes' starts: its drape
// curve is shown, not compared. Printed: the time each method takes to each
// level.
// One method of the accuracy studies: the solver, its iteration cap and
// acceleration (Chebyshev's ρ, 0: off; Anderson's window, 0: off).
struct AccuracyMethod {
  std::string name;
  Solver solver;
  int iterations;
  double rho;
  int anderson;
  // `base`'s forces and colliders with this method, every residual recorded
  // and `tolerance` (relative to the start) as the stop.
  StepSettings settings(const StepSettings& base, double tolerance) const {
    StepSettings st = base;
    st.solver = solver;
    st.solve.iterations = iterations;
    st.solve.tolerance = tolerance;
    st.solve.record_residuals = true;
    st.solve.chebyshev = rho > 0;
    if (rho > 0) st.solve.chebyshev_rho = rho;
    st.solve.anderson = anderson;
    return st;
  }
};

// The step's scale: ‖∇E(y)‖ at its inertial prediction y.
double step_scale(const ClothState& state, double h, const StepSettings& settings) {
  const Eigen::MatrixX3d y = inertial_prediction(state, h, settings);
  return incremental_gradient(*state.system, y, y, h).norm();
}

struct AccuracyScene {
  std::string name;
  std::shared_ptr<const SpringSystem> system;
  StepSettings base;  // the scene's forces and colliders
  ClothState state;   // the state the measured step starts from
  std::shared_ptr<const LocalGlobalSolver> solver;
};

std::vector<AccuracyScene> accuracy_scenes(int n, double h) {
  std::vector<AccuracyScene> scenes;
  const double saved = g_density;
  for (double density : {0.1, 6400.0}) {
    g_density = density;
    AccuracyScene sc{density < 1 ? "light" : "heavy", std::make_shared<const SpringSystem>(curtain(n)),
                     windy(Solver::local_global, 100), {}, {}};
    sc.solver = std::make_shared<const LocalGlobalSolver>(*sc.system, h);
    sc.state = rest_state(sc.system);
    for (int f = 0; f < 20; ++f) sc.state = step(sc.state, h, sc.base, sc.solver.get()).state;
    scenes.push_back(sc);
    if (density < 1) {  // the same step with local/global started from y, as Newton is
      sc.name = "light_from_y";
      sc.base.start = Start::prediction;
      scenes.push_back(std::move(sc));
    }
  }
  g_density = saved;
  const int d = n == 81 ? 31 : 21;
  AccuracyScene drape{"drape",
                      std::make_shared<const SpringSystem>(grid_cloth(d, d, Eigen::Vector3d(-0.8, 1.2, -0.8),
                                                                      Eigen::Vector3d(1.6, 0, 0),
                                                                      Eigen::Vector3d(0, 0, 1.6), 1, 1e4, 1e4, 1e2)),
                      windy(Solver::local_global, 20), {}, {}};
  drape.base.wind_speed = 0;
  drape.base.damping = 0.2;
  drape.base.ground = true;
  drape.base.friction = 0.5;
  drape.base.spheres.push_back({Eigen::Vector3d(0, 0.5, 0), 0.5});
  drape.solver = std::make_shared<const LocalGlobalSolver>(*drape.system, h, contact_weight(*drape.system));
  drape.state = rest_state(drape.system);
  for (int f = 0; f < 30; ++f) drape.state = step(drape.state, h, drape.base, drape.solver.get()).state;
  scenes.push_back(std::move(drape));
  return scenes;
}

void accuracy_study(int n, int runs) {
  const double h = 1.0 / 30;
  const std::vector<AccuracyScene> scenes = accuracy_scenes(n, h);
  loom::bench::Csv csv("cloth_accuracy", {"curve", "scene", "method", "iteration", "seconds", "residual",
                                          "residual_to_own_start", "load"});
  const std::vector<AccuracyMethod> methods = {{"plain", Solver::local_global, 3000, 0, 0},
                                               {"chebyshev 0.99", Solver::local_global, 3000, 0.99, 0},
                                               {"chebyshev 0.999", Solver::local_global, 3000, 0.999, 0},
                                               {"anderson 6", Solver::local_global, 3000, 0, 6},
                                               {"newton", Solver::newton, 200, 0, 0}};
  const double tolerances[] = {1e-2, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8};
  for (std::size_t sc = 0; sc < scenes.size(); ++sc) {
    const double scale = step_scale(scenes[sc].state, h, scenes[sc].base);
    std::printf("\n%s (%d vertices), load %s, |grad E(y)| = %.3g: seconds to |grad E| / |grad E(y)| (iterations)\n",
                scenes[sc].name.c_str(), scenes[sc].system->vertices(), load().c_str(), scale);
    for (const AccuracyMethod& m : methods) {
      StepSettings st = m.settings(scenes[sc].base, 1e-9);
      Clock::time_point t0;
      std::vector<double> stamps;
      st.solve.after_iteration = [&] { stamps.push_back(seconds_since(t0)); };
      std::vector<std::vector<double>> all;
      SolveReport report;
      loom::cloth::NewtonWorkspace newton_workspace;
      for (int r = 0; r <= runs; ++r) {  // run 0 warms up (Newton's symbolic analysis)
        stamps.clear();
        t0 = Clock::now();
        report = step(scenes[sc].state, h, st, scenes[sc].solver.get(), &newton_workspace).report;
        if (r > 0) all.push_back(stamps);
      }
      std::vector<double> median(stamps.size());
      for (std::size_t k = 0; k < median.size(); ++k) {
        std::vector<double> at;
        for (const auto& a : all) at.push_back(a[k]);
        std::sort(at.begin(), at.end());
        median[k] = at[at.size() / 2];
      }
      const std::size_t count = std::min(median.size(), report.residuals.size());
      std::vector<double> residual(count);
      for (std::size_t k = 0; k < count; ++k) {
        residual[k] = report.residuals[k] * report.start_gradient / scale;
        csv.row({scenes[sc].name + ", " + m.name, scenes[sc].name, m.name, static_cast<long long>(k + 1), median[k],
                 residual[k], report.residuals[k], load()});
      }
      std::printf("  %-16s start %.2g", m.name.c_str(), report.start_gradient / scale);
      for (double tol : tolerances) {
        std::size_t k = 0;
        while (k < count && residual[k] > tol) ++k;
        if (k < count)
          std::printf("  %g: %.4f s (%zu)", tol, median[k], k + 1);
        else
          std::printf("  %g: not in %zu (min %.2g)", tol, count,
                      count ? *std::min_element(residual.begin(), residual.end()) : 1.0);
      }
      std::printf("\n");
    }
  }
  csv.save();
  for (const auto& sc : scenes) {
    loom::bench::Csv part("cloth_accuracy_" + sc.name, csv.columns());
    for (const auto& row : csv.rows())
      if (std::get<std::string>(row[1]) == sc.name) part.row(row);
    loom::bench::plot(part, {"seconds", "residual", "method",
                             sc.name + " " + std::to_string(sc.system->vertices()) +
                                 " vertices, one step (h = 1/30): |grad E| / |grad E(y)| vs time",
                             true, true, ""});
  }
}

// The same question over a run: the light 81² curtain's steps at frames 10,
// 15, ..., 40 (each from the state local/global with 100 iterations left),
// the time each method takes to ‖∇E‖ / ‖∇E(y)‖ = 1e-6 (first iterate at or
// below it), one run each: whether the ratio on the step above is typical.
void accuracy_over_frames(int n) {
  const double h = 1.0 / 30;
  const double saved = g_density;
  g_density = 0.1;
  auto system = std::make_shared<const SpringSystem>(curtain(n));
  g_density = saved;
  const LocalGlobalSolver lg(*system, h);
  const StepSettings base = windy(Solver::local_global, 100);
  ClothState state = rest_state(system);
  loom::cloth::NewtonWorkspace newton_workspace;
  loom::bench::Csv csv("cloth_accuracy_frames", {"frame", "method", "seconds", "iterations", "start", "load"});
  std::printf("\nlight %dx%d curtain over a run: seconds to |grad E| / |grad E(y)| = 1e-6 (iterations), load %s\n", n,
              n, load().c_str());
  const AccuracyMethod methods[] = {{"anderson 6", Solver::local_global, 1500, 0, 6},
                                    {"chebyshev 0.999", Solver::local_global, 1500, 0.999, 0},
                                    {"newton", Solver::newton, 60, 0, 0}};
  for (int frame = 0; frame <= 40; ++frame) {
    if (frame >= 10 && frame % 5 == 0) {
      const double scale = step_scale(state, h, base);
      std::printf("  frame %d:", frame);
      for (const AccuracyMethod& m : methods) {
        StepSettings st = m.settings(base, 1e-14);
        std::vector<double> stamps;
        const Clock::time_point t0 = Clock::now();
        st.solve.after_iteration = [&] { stamps.push_back(seconds_since(t0)); };
        const SolveReport report = step(state, h, st, &lg, &newton_workspace).report;
        const double start = report.start_gradient / scale;
        std::size_t k = 0;
        while (k < report.residuals.size() && report.residuals[k] * start > 1e-6) ++k;
        const bool reached = k < report.residuals.size();
        csv.row({static_cast<long long>(frame), m.name, reached ? stamps[k] : -1.0,
                 static_cast<long long>(reached ? k + 1 : 0), start, load()});
        if (reached)
          std::printf("  %s %.3f s (%zu)", m.name.c_str(), stamps[k], k + 1);
        else
          std::printf("  %s not in %d", m.name.c_str(), m.iterations);
      }
      std::printf("\n");
    }
    state = step(state, h, base, &lg).state;
  }
  csv.save();
}

const char* start_name(Start start) {
  return start == Start::prediction ? "prediction" : start == Start::extrapolation ? "extrapolation" : "lower_energy";
}

// Where local/global starts each step (prediction y, extrapolation
// x_n + h v_n, or the one of the two with the lower E), three ways:
//  at rest: a 21² curtain pinned at the top, damped (c = 2/s), no wind,
//    300 frames of 10 iterations; largest distance from its equilibrium over
//    the cloth's size (the equilibrium: converged Newton steps from there
//    until nothing moves by 1e-14 m);
//  in motion: the swinging 25² corner curtain of cloth_frames100, RMS error
//    after 100 frames against converged Newton;
//  cost: 81² windy curtain, one frame from a swinging state, error against
//    converged Newton and CPU time, at 10 iterations and with tolerances
//    (iteration cap 100).
void start_study(int runs) {
  const double h = 1.0 / 30;
  loom::bench::Csv csv("cloth_start" + g_suffix,
                       {"case", "start", "iterations", "tolerance", "mean_iterations", "cpu_seconds", "error", "load"});
  {
    auto system = std::make_shared<const SpringSystem>(curtain(21));
    const LocalGlobalSolver lg(*system, h);
    for (Start start : {Start::prediction, Start::extrapolation, Start::lower_energy}) {
      StepSettings st = windy(Solver::local_global, 10);
      st.wind_speed = 0;
      st.damping = 2;
      st.start = start;
      ClothState s = rest_state(system);
      for (int f = 0; f < 300; ++f) s = step(s, h, st, &lg).state;
      const double motion = (step(s, h, st, &lg).state.x - s.x).cwiseAbs().maxCoeff();
      StepSettings exact = reference_settings();
      exact.wind_speed = 0;
      exact.damping = 50;
      ClothState e = s;
      for (int f = 0; f < 2000; ++f) {
        ClothState next = step(e, h, exact, nullptr).state;
        const double moved = (next.x - e.x).cwiseAbs().maxCoeff();
        e = std::move(next);
        if (moved < 1e-14) break;
      }
      const double off = (s.x - e.x).rowwise().norm().maxCoeff();
      std::printf("at rest, start %-13s: %.3g of the size off the equilibrium, motion per frame %.2g m\n",
                  start_name(start), off, motion);
      csv.row({std::string("rest_21"), std::string(start_name(start)), 10LL, 0.0, 10.0, 0.0, off, load()});
    }
  }
  {
    const int n = 25;
    SpringSystem corners = grid_cloth(n, n, Eigen::Vector3d(-0.5, 0.5, 0), Eigen::Vector3d(1, 0, 0),
                                      Eigen::Vector3d(0, 1, 0), g_density, 1e5, 1e5, 1e5);
    corners.fixed[grid_index(n, 0, n - 1)] = corners.fixed[grid_index(n, n - 1, n - 1)] = 1;
    auto system = std::make_shared<const SpringSystem>(corners);
    const LocalGlobalSolver lg(*system, h);
    auto run = [&](StepSettings st) {
      st.wind_speed = 0;
      st.damping = 0;
      ClothState s = rest_state(system);
      for (int i = 0; i < s.v.rows(); ++i)
        if (!system->fixed[i]) s.v(i, 2) = 1;
      for (int f = 0; f < 100; ++f) s = step(s, h, st, st.solver == Solver::local_global ? &lg : nullptr).state;
      return s.x;
    };
    StepSettings reference = reference_settings();
    reference.solve.iterations = 200;  // the light cloth's Newton converges linearly: capped
    const Eigen::MatrixX3d ref = run(reference);
    for (int it : {1, 10, 50})
      for (Start start : {Start::prediction, Start::extrapolation, Start::lower_energy}) {
        StepSettings st = windy(Solver::local_global, it);
        st.start = start;
        const double err = (run(st) - ref).norm() / std::sqrt(static_cast<double>(system->vertices()));
        std::printf("motion, %d iterations, start %-13s: RMS error after 100 frames %.3g m\n", it, start_name(start),
                    err);
        csv.row({std::string("motion_25_corners"), std::string(start_name(start)), static_cast<long long>(it), 0.0,
                 static_cast<double>(it), 0.0, err, load()});
      }
  }
  auto system = std::make_shared<const SpringSystem>(curtain(81));
  const LocalGlobalSolver lg(*system, h);
  ClothState state = rest_state(system);
  for (int f = 0; f < 20; ++f) state = step(state, h, windy(Solver::local_global, 100), &lg).state;
  StepSettings reference = reference_settings();
  reference.solve.iterations = 300;  // capped: the light cloth's Newton converges linearly
  const Eigen::MatrixX3d ref = step(state, h, reference, nullptr).state.x;
  const double moved = (ref - state.x).norm();
  struct Setting {
    int iterations;
    double tolerance;
  };
  for (Setting set : {Setting{10, 0}, Setting{100, 1e-2}, Setting{100, 1e-3}, Setting{100, 1e-4}})
    for (Start start : {Start::prediction, Start::extrapolation, Start::lower_energy}) {
      StepSettings st = windy(Solver::local_global, set.iterations, set.tolerance);
      st.start = start;
      StepResult r;
      const WallCpu t = time_wall_cpu([&] { r = step(state, h, st, &lg); }, runs);
      const double err = (r.state.x - ref).norm() / moved;
      std::printf("81² frame, %d iterations, tolerance %g, start %-13s: %d iterations, %.2f ms CPU, error %.3g\n",
                  set.iterations, set.tolerance, start_name(start), r.report.iterations, 1e3 * t.cpu, err);
      csv.row({std::string("frame_81"), std::string(start_name(start)), static_cast<long long>(set.iterations),
               set.tolerance, static_cast<double>(r.report.iterations), t.cpu, err, load()});
    }
  csv.save();
}
}  // namespace

int main(int argc, char** argv) {
  // As `loom` runs (loom/process_start.hpp): OpenBLAS and CHOLMOD's OpenMP on
  // one thread, malloc in huge pages; this program links CHOLMOD, so libgomp
  // reads its limit at start and the settings take effect in the re-executed
  // process.
  loom::prepare_process(argv, /*evaluates_graphs=*/true);
  loom::bench::Cli cli("bench_cloth",
                       "Newton against local/global (plain, Chebyshev) on pinned curtains, and the "
                       "assignment's cuboid drop; writes cloth_* CSV and plots.");
  bool quick = false;
  std::vector<std::string> modes;
  double density = g_density;
  cli.quick(quick, "fewer sizes and runs")
      .option("--density", density,
              "curtain density in kg/m² (when given: CSV names get _densityD, no cuboid by default)")
      .modes(modes,
             {{"cuboid", "the cuboid dropped on the ground, k = 1e3, 1e4, 1e5 (cloth_cuboid)"},
              {"frame", "one frame of the 81² curtain: time against error (cloth_frame)"},
              {"frames100", "100 frames of the 25² curtain: error against time (cloth_frames100)"},
              {"convergence", "local/global residual per iteration (cloth_convergence)"},
              {"start", "where local/global starts: at rest, in motion, cost per frame (cloth_start)"},
              {"scaling", "factorization and frame time, memory, from 41² to 321² (cloth_scaling)"},
              {"accuracy", "time against relative |grad E| per step: plain, Chebyshev, Anderson, Newton on the "
                           "light and heavy curtains and the drape (cloth_accuracy)"},
              {"accuracy_frames", "time to |grad E| / |grad E(y)| = 1e-6 at frames 10-40 of the light curtain: "
                                  "Anderson, Chebyshev 0.999, Newton (cloth_accuracy_frames)"}},
             "parts to run (default: all; the cuboid not with --density)")
      .threads();
  cli.parse(argc, argv);
  if (cli.given("--density")) {
    if (!(density > 0)) {
      std::fprintf(stderr, "bench_cloth: --density must be positive (kg/m²), got %g\n", density);
      return 2;
    }
    g_density = density;
    std::ostringstream name;
    name << "_density" << density;
    g_suffix = name.str();
  }
  std::printf("load at start: %s\n", load().c_str());
  if (modes.empty() ? g_suffix.empty() : loom::bench::wants(modes, "cuboid")) cuboid_study();
  if (loom::bench::wants(modes, "frame")) frame_study(quick ? 41 : 81, quick ? 3 : 7);
  if (loom::bench::wants(modes, "frames100")) trajectory_study(quick ? 15 : 25, 100);
  if (loom::bench::wants(modes, "convergence")) convergence_study(quick ? 41 : 81);
  if (loom::bench::wants(modes, "start")) start_study(quick ? 3 : 7);
  if (loom::bench::wants(modes, "scaling"))
    scaling_study(quick ? std::vector<int>{41, 81} : std::vector<int>{41, 81, 161, 321}, quick ? 3 : 5);
  if (loom::bench::wants(modes, "accuracy")) accuracy_study(quick ? 41 : 81, quick ? 1 : 3);
  if (loom::bench::wants(modes, "accuracy_frames")) accuracy_over_frames(quick ? 41 : 81);
  std::printf("load at end: %s\n", load().c_str());
  return 0;
}
