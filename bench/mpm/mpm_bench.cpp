// MLS-MPM throughput, strong scaling, memory, and time-vs-error; no peer MPM
// library is installed on this machine (Taichi is not packaged by Debian), so
// Loom is measured alone against the targets. The timed modes run as
// `loom run` does (loom/process_start.hpp): malloc's memory on 2-MiB pages
// (docs/architecture.md, decision 29; GLIBC_TUNABLES=glibc.malloc.hugetlb=0
// measures 4-KiB pages).
//
//   The timed modes and `count` run substeps on the particles in block order, the
//   order advance() puts them in at the start of every frame (Solver::in_block_order;
//   the emitter leaves them in Morton order, which no frame runs in).
//   throughput: particle-substeps per second (wall and per CPU-second) for
//     2D: mpm88's fluid scaled to 1M particles in [0.2, 0.6]² on 512²
//     3D: 1M fluid / elastic particles in [0.2, 0.6]³ on 128³
//     at 1 and 2 threads (--threads N to go further), medians of 5 runs.
//   limit: the same scenes against the memory-bandwidth limit, in one run,
//     alternating round by round: Loom's rate, a loop that moves the substep's
//     bytes and computes nothing (mpm_traffic.hpp), and the STREAM triad
//     (bench/harness/stream_bandwidth); fraction of the limit = bytes per
//     particle-substep × rate / triad bandwidth. Also the core's clock, peak
//     SSE2 flop rate and divider rate (core_rate.hpp), for the compute limits
//     with callgrind's counts.
//   count: a few substeps of one scene and nothing else, to count instructions
//     (on one thread: callgrind's toggle counts only the thread that enters it;
//     the one mode that does not start again on huge pages, below, since
//     valgrind would not follow the exec):
//     valgrind --tool=callgrind --toggle-collect='loom::mpm::Solver<*>::substep*'
//       build/bin/bench_mpm count --threads 1 --scene 0 --particles 100000 --substeps 2
//   nbody: the NBody node's direct sum (orbits.cpp), pair interactions per
//     second on one thread (the code is serial), for `n` bodies with mass.
//   error: the centre of mass and the particle positions of an elastic block
//     dropped for 1 s, against a run with 16× smaller Δt, over Δt; and over the
//     grid resolution against the finest grid.
#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <random>
#include <string>
#include <thread>

#include "alternating.hpp"
#include "bench_harness.hpp"
#include "core_rate.hpp"
#include "emitters.hpp"
#include "mls_mpm.hpp"
#include "mpm_traffic.hpp"
#include "loom/process_start.hpp"
#include "orbits.hpp"
#include "stream_bandwidth.hpp"

namespace {

using namespace loom::mpm;
using Clock = std::chrono::steady_clock;

template <int D>
Particles<D> cube(Material m, double E, int count, std::uint64_t seed = 1) {
  EmitOptions o;
  o.material = m;
  o.E = E;
  o.sampling = Sampling::random;
  o.count = count;
  o.spacing = 1.0 / 1024;
  o.seed = seed;
  using Vec = Eigen::Matrix<double, D, 1>;
  return fill_shape<D>([](const Vec&) { return true; }, Vec::Constant(0.2), Vec::Constant(0.6), o);
}

struct Throughput {
  double wall, cpu;  // M particle-substeps per second
};

template <int D>
Throughput throughput(Particles<D> ps, int resolution, int threads, int substeps, int runs) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  Settings s;
  s.resolution = resolution;
  Solver<D> solver(s);
  ps = solver.in_block_order(ps);
  double cpu_total = 0;
  const auto t = loom::bench::time_median(
      [&] {
        const double c0 = loom::bench::process_cpu_seconds();
        for (int k = 0; k < substeps; ++k) solver.substep(ps, 2e-5);
        cpu_total += loom::bench::process_cpu_seconds() - c0;
      },
      runs);
  const double work = static_cast<double>(ps.size()) * substeps / 1e6;
  return {work / t.median, work * (runs + 1) / cpu_total};
}

template <int D>
std::size_t bytes_per_particle() {
  using P = Particles<D>;
  return sizeof(typename P::Vec) * 2 + sizeof(typename P::Mat) * 2 + sizeof(double) * 5 +
         sizeof(Material) + sizeof(Eigen::Vector3f) + 2 * sizeof(int)  // + binning workspace
         + sizeof(typename P::Mat);                                      // + P2G's affine matrices
}

struct Scene {
  std::string name;
  int dim;
  Material m;
  int resolution() const { return dim == 2 ? 512 : 128; }
  std::string grid() const { return dim == 2 ? "512^2" : "128^3"; }
  int substeps(bool quick) const { return dim == 2 ? (quick ? 5 : 10) : (quick ? 2 : 4); }
};

const std::vector<Scene>& scenes() {
  static const std::vector<Scene> all = {{"2D fluid (mpm88) 512^2", 2, Material::fluid},
                                         {"2D elastic 512^2", 2, Material::elastic},
                                         {"3D fluid 128^3", 3, Material::fluid},
                                         {"3D elastic 128^3", 3, Material::elastic}};
  return all;
}

void run_throughput(int max_threads, bool quick) {
  loom::bench::Csv csv("mpm_throughput", {"scene", "threads", "particles", "grid", "Mps_wall",
                                          "Mps_cpu", "bytes_per_particle", "load"});
  const int n = quick ? 200000 : 1000000;
  for (const Scene& scene : scenes()) {
    for (int threads = 1; threads <= max_threads; threads *= 2) {
      Throughput t{};
      if (scene.dim == 2)
        t = throughput(cube<2>(scene.m, 400, n), scene.resolution(), threads, scene.substeps(quick), 5);
      else
        t = throughput(cube<3>(scene.m, 400, n), scene.resolution(), threads, scene.substeps(quick), 5);
      csv.row({scene.name, static_cast<long long>(threads), static_cast<long long>(n), scene.grid(), t.wall, t.cpu,
               static_cast<long long>(scene.dim == 2 ? bytes_per_particle<2>() : bytes_per_particle<3>()),
               loom::bench::load_average()});
    }
  }
  csv.save();
  loom::bench::plot(csv, {"threads", "Mps_wall", "scene", "MLS-MPM particle-substeps per second (M)", false, false, ""});
  // Per CPU-second: what one core delivers, readable on a loaded machine too.
  loom::bench::plot(csv, {"threads", "Mps_cpu", "scene", "MLS-MPM particle-substeps per CPU-second (M)",
                          false, false, "_cpu"});
}

// One row of mpm_limit: Loom, the streaming loop of the same bytes and the
// triad, alternating round by round at `threads`. Returns the loop's checksum.
template <int D>
double limit_row(loom::bench::Csv& csv, const Scene& scene, Particles<D> ps, int threads, int substeps, int runs,
                 loom::bench::StreamArrays& arrays) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  arrays.touch();
  Settings s;
  s.resolution = scene.resolution();
  Solver<D> solver(s);
  ps = solver.in_block_order(ps);
  solver.substep(ps, 2e-5);
  long with_mass = 0;
  for (const auto& node : solver.grid()) with_mass += node[D] > 0;
  const long nodes = solver.reachable_nodes();  // the nodes a substep clears and updates
  Particles<D> proxy_ps = ps;
  traffic::StreamingProxy<D> proxy(nodes, with_mass);
  const auto& triad = loom::bench::stream_kernel("triad");
  const auto t = loom::bench::time_alternating(runs, {[&] {
                                                        for (int k = 0; k < substeps; ++k) solver.substep(ps, 2e-5);
                                                      },
                                                      [&] {
                                                        for (int k = 0; k < substeps; ++k) proxy.run(proxy_ps);
                                                      },
                                                      [&] { arrays.run(triad); }});
  const double work = static_cast<double>(ps.size()) * substeps;
  const double loom_rate = work / t[0].wall, proxy_rate = work / t[1].wall, loom_cpu_rate = work / t[0].cpu;
  const double triad_bandwidth = arrays.bytes(triad) / t[2].wall;
  const double particle = traffic::particle_bytes<D>(scene.m);
  const double grid = traffic::grid_bytes<D>(nodes, with_mass) / ps.size();
  const double bytes = particle + grid;
  csv.row({scene.name, static_cast<long long>(threads), static_cast<long long>(ps.size()), scene.grid(),
           loom_rate * 1e-6, loom_cpu_rate * 1e-6, proxy_rate * 1e-6, particle, grid, bytes, bytes * loom_rate * 1e-9,
           bytes * proxy_rate * 1e-9, triad_bandwidth * 1e-9, bytes * loom_rate / triad_bandwidth,
           loom_rate / proxy_rate, loom::bench::load_average()});
  return proxy.checksum();
}

void run_limit(int max_threads, bool quick) {
  loom::bench::Csv core("mpm_core_rate",
                        {"clock_ghz", "sse2_peak_gflops", "divisions_per_ns", "square_roots_per_ns", "load"});
  core.row({loom::bench::core_clock_hz() * 1e-9, loom::bench::core_peak_flops() * 1e-9,
            loom::bench::core_divisions() * 1e-9, loom::bench::core_square_roots() * 1e-9,
            loom::bench::load_average()});
  core.save();
  loom::bench::Csv csv("mpm_limit",
                       {"scene", "threads", "particles", "grid", "Mps_wall", "Mps_cpu", "proxy_Mps", "particle_bytes",
                        "grid_bytes", "bytes_per_particle_substep", "loom_GB_per_s", "proxy_GB_per_s", "triad_GB_per_s",
                        "fraction_of_triad", "fraction_of_proxy", "load"});
  const int n = quick ? 200000 : 1000000;
  loom::bench::StreamArrays arrays(quick ? 128 : 256);
  double checksum = 0;  // printed, so that no compiler drops the loops
  for (const Scene& scene : scenes())
    for (int threads = 1; threads <= max_threads; threads *= 2) {
      if (scene.dim == 2)
        checksum += limit_row<2>(csv, scene, cube<2>(scene.m, 400, n), threads, scene.substeps(quick), 5, arrays);
      else
        checksum += limit_row<3>(csv, scene, cube<3>(scene.m, 400, n), threads, scene.substeps(quick), 5, arrays);
    }
  std::printf("checksums: streaming loop %g, triad %.1f\n", checksum, arrays.checksum());
  csv.save();
  loom::bench::plot(csv, {"threads", "fraction_of_triad", "scene",
                          "MLS-MPM bytes moved per second / STREAM triad bandwidth", false, false, ""});
}

// n bodies with mass, uniform in the unit ball, softened, at rest.
NBodySystem random_cluster(int n) {
  NBodySystem s;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  while (s.size() < n) {
    const Eigen::Vector3d x(u(rng), u(rng), u(rng));
    if (x.squaredNorm() > 1) continue;
    s.x.push_back(x);
    s.v.push_back(Eigen::Vector3d::Zero());
    s.m.push_back(1.0 / n);
  }
  s.softening = 0.05;
  s.prepare();
  return s;
}

// Leapfrog evaluates the accelerations twice a step: n (n − 1) pairs.
void run_nbody(bool quick) {
  // The code is serial: its CPU time is what it costs on a quiet core, even on a
  // loaded machine (cycles_per_pair from it and the measured clock).
  loom::bench::Csv csv("mpm_nbody", {"bodies", "steps", "Mpairs_per_s", "Mpairs_per_cpu_s", "cycles_per_pair", "load"});
  const double clock = loom::bench::core_clock_hz();
  for (int n : {256, 1024, 4096}) {
    NBodySystem s = random_cluster(n);
    const int steps = std::max(1, (quick ? 1 << 22 : 1 << 24) / (n * n));
    const auto t = loom::bench::time_alternating(5, {[&] {
                                                   for (int k = 0; k < steps; ++k) step(s, 1e-4, Integrator::leapfrog);
                                                 }})[0];
    const double pairs = double(n) * (n - 1) * steps;
    csv.row({static_cast<long long>(n), static_cast<long long>(steps), pairs / t.wall * 1e-6, pairs / t.cpu * 1e-6,
             t.cpu / pairs * clock, loom::bench::load_average()});
  }
  csv.save();
  loom::bench::plot(csv, {"bodies", "Mpairs_per_s", "", "NBody direct sum: pair interactions per second (M), 1 thread",
                          true, false, ""});
}

// `substeps` substeps of one scene (or all, scene < 0) and nothing timed: for
// counting instructions under callgrind.
void run_count(int scene_index, int particles, int substeps) {
  for (int k = 0; k < static_cast<int>(scenes().size()); ++k) {
    if (scene_index >= 0 && k != scene_index) continue;
    const Scene& scene = scenes()[static_cast<std::size_t>(k)];
    Settings s;
    s.resolution = scene.resolution();
    if (scene.dim == 2) {
      Solver<2> solver(s);
      auto ps = solver.in_block_order(cube<2>(scene.m, 400, particles));
      for (int i = 0; i < substeps; ++i) solver.substep(ps, 2e-5);
    } else {
      Solver<3> solver(s);
      auto ps = solver.in_block_order(cube<3>(scene.m, 400, particles));
      for (int i = 0; i < substeps; ++i) solver.substep(ps, 2e-5);
    }
    std::printf("%s: %d particles, %d substeps\n", scene.name.c_str(), particles, substeps);
  }
}

// An elastic block dropped from rest onto the floor (contact at t ≈ 0.23 s).
Particles<2> dropped_block() {
  EmitOptions o;
  o.material = Material::elastic;
  o.E = 300;
  o.spacing = 1.0 / 256;
  o.sampling = Sampling::grid;
  return fill_shape<2>([](const Eigen::Vector2d&) { return true; }, Eigen::Vector2d(0.4, 0.3),
                       Eigen::Vector2d(0.6, 0.5), o);
}

Particles<2> simulate(int resolution, double dt_cap, double cfl, double seconds) {
  auto ps = dropped_block();
  Settings s;
  s.resolution = resolution;
  s.dt_max = dt_cap;
  s.cfl = cfl;
  s.max_substeps = 10'000'000;  // the references take 160,000 substeps in their one advance
  Solver<2> solver(s);
  solver.advance(ps, seconds);
  return ps;
}

Eigen::Vector2d centre_of_mass(const Particles<2>& ps) {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  double m = 0;
  for (int i = 0; i < ps.size(); ++i) c += ps.mass[i] * ps.x[i], m += ps.mass[i];
  return c / m;
}

double rms_distance(const Particles<2>& a, const Particles<2>& b) {
  double sum = 0;
  for (int i = 0; i < a.size(); ++i) sum += (a.x[i] - b.x[i]).squaredNorm();
  return std::sqrt(sum / a.size());
}

void run_error(bool quick) {
  const double seconds = quick ? 0.25 : 1.0;
  loom::bench::Csv csv("mpm_error_dt", {"dt", "seconds", "com_error", "rms_position_error", "load"});
  // Δt set by the cap (cfl = 1 leaves the cap in charge; the CFL limit at 64² is ≈ 8.6e-4).
  for (double dt : {8e-4, 4e-4, 2e-4, 1e-4}) {
    const auto t0 = Clock::now();
    const auto coarse = simulate(64, dt, 1.0, seconds);
    const double t = std::chrono::duration<double>(Clock::now() - t0).count();
    const auto fine = simulate(64, dt / 16, 1.0, seconds);
    csv.row({dt, t, (centre_of_mass(coarse) - centre_of_mass(fine)).norm(), rms_distance(coarse, fine),
             loom::bench::load_average()});
  }
  csv.save();
  loom::bench::plot(csv, {"dt", "rms_position_error", "", "Positions after 1 s vs 16x smaller dt (64^2)",
                          true, true, ""});
  loom::bench::plot(csv, {"dt", "com_error", "", "Centre of mass after 1 s vs 16x smaller dt (64^2)",
                          true, true, "_com"});

  loom::bench::Csv grid("mpm_error_grid", {"resolution", "seconds", "com_error", "rms_position_error", "load"});
  const auto finest = simulate(256, 1e-4, 0.4, seconds);
  for (int res : {32, 64, 128}) {
    const auto t0 = Clock::now();
    const auto ps = simulate(res, 1e-4, 0.4, seconds);
    const double t = std::chrono::duration<double>(Clock::now() - t0).count();
    grid.row({static_cast<long long>(res), t, (centre_of_mass(ps) - centre_of_mass(finest)).norm(),
              rms_distance(ps, finest), loom::bench::load_average()});
  }
  grid.save();
  loom::bench::plot(grid, {"resolution", "rms_position_error", "",
                           "Positions after 1 s vs a 256^2 grid", true, true, ""});
}

}  // namespace

int main(int argc, char** argv) {
  loom::bench::Cli cli("bench_mpm", "MLS-MPM throughput and time-vs-error.");
  bool quick = false;
  int max_threads = 2;
  int scene = -1, particles = 100000, substeps = 2;
  std::vector<std::string> modes;
  cli.quick(quick, "200k particles and half the substeps; 0.25 s instead of 1 s of simulation")
      .threads(max_threads, "the throughput runs at 1, 2, 4, ... up to N threads (0: all cores)")
      .modes(
          modes,
          {{"throughput", "particle-substeps per second: 2D 1M @ 512², 3D 1M @ 128³ (mpm_throughput)"},
           {"limit", "the throughput scenes against the memory-bandwidth limit and the core's rate "
                     "(mpm_limit, mpm_core_rate)"},
           {"nbody", "the NBody direct sum: pair interactions per second (mpm_nbody)"},
           {"error", "an elastic block's error over Δt and grid resolution (mpm_error_*)"},
           {"count", "only --substeps substeps of --scene, for callgrind with --threads 1 (not in the default set)"}},
          "parts to run (default: all but count)")
      .option("--scene", scene, "count: 0 2D fluid, 1 2D elastic, 2 3D fluid, 3 3D elastic (-1: all)")
      .option("--particles", particles, "count: particles")
      .option("--substeps", substeps, "count: substeps");
  cli.parse(argc, argv);
  if (scene < -1 || scene >= static_cast<int>(scenes().size()) || particles < 1 || substeps < 0) {
    std::fprintf(stderr, "bench_mpm: --scene must be -1..%d, --particles at least 1, --substeps at least 0\n",
                 static_cast<int>(scenes().size()) - 1);
    return 2;
  }
  // After the arguments are read (all valid: the program starts again with them).
  const bool counting = !modes.empty() && loom::bench::wants(modes, "count");
  if (!counting) loom::prepare_process(argv, /*evaluates_graphs=*/true);
  if (max_threads == 0) max_threads = static_cast<int>(std::thread::hardware_concurrency());
  if (loom::bench::wants(modes, "throughput")) run_throughput(max_threads, quick);
  if (loom::bench::wants(modes, "limit")) run_limit(max_threads, quick);
  if (loom::bench::wants(modes, "nbody")) run_nbody(quick);
  if (loom::bench::wants(modes, "error")) run_error(quick);
  if (counting) run_count(scene, particles, substeps);
}
