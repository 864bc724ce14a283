// MLS-MPM throughput, strong scaling, memory, and time-vs-error; no peer MPM
// library is installed on this machine (Taichi is not packaged by Debian), so
// Loom is measured alone against the targets.
//
//   throughput: particle-substeps per second (wall and per CPU-second) for
//     2D: mpm88's fluid scaled to 1M particles in [0.2, 0.6]² on 512²
//     3D: 1M fluid / elastic particles in [0.2, 0.6]³ on 128³
//     at 1 and 2 threads (--threads N to go further), medians of 5 runs.
//   error: the centre of mass and the particle positions of an elastic block
//     dropped for 1 s, against a run with 16× smaller Δt, over Δt; and over the
//     grid resolution against the finest grid.
#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <string>
#include <thread>

#include "bench_harness.hpp"
#include "emitters.hpp"
#include "mls_mpm.hpp"

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
         sizeof(Material) + sizeof(Eigen::Vector3f) + 2 * sizeof(int);  // + binning workspace
}

void run_throughput(int max_threads, bool quick) {
  loom::bench::Csv csv("mpm_throughput", {"scene", "threads", "particles", "grid", "Mps_wall",
                                          "Mps_cpu", "bytes_per_particle", "load"});
  const int n = quick ? 200000 : 1000000;
  struct Scene {
    std::string name;
    int dim;
    Material m;
  };
  for (const Scene& scene : {Scene{"2D fluid (mpm88) 512^2", 2, Material::fluid},
                             Scene{"2D elastic 512^2", 2, Material::elastic},
                             Scene{"3D fluid 128^3", 3, Material::fluid},
                             Scene{"3D elastic 128^3", 3, Material::elastic}}) {
    for (int threads = 1; threads <= max_threads; threads *= 2) {
      Throughput t{};
      if (scene.dim == 2)
        t = throughput(cube<2>(scene.m, 400, n), 512, threads, quick ? 5 : 10, 5);
      else
        t = throughput(cube<3>(scene.m, 400, n), 128, threads, quick ? 2 : 4, 5);
      csv.row({scene.name, static_cast<long long>(threads), static_cast<long long>(n),
               scene.dim == 2 ? std::string("512^2") : std::string("128^3"), t.wall, t.cpu,
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
  std::vector<std::string> modes;
  cli.quick(quick, "200k particles and half the substeps; 0.25 s instead of 1 s of simulation")
      .threads(max_threads, "the throughput runs at 1, 2, 4, ... up to N threads (0: all cores)")
      .modes(modes,
             {{"throughput", "particle-substeps per second: 2D 1M @ 512², 3D 1M @ 128³ (mpm_throughput)"},
              {"error", "an elastic block's error over Δt and grid resolution (mpm_error_*)"}},
             "parts to run (default: both)");
  cli.parse(argc, argv);
  if (max_threads == 0) max_threads = static_cast<int>(std::thread::hardware_concurrency());
  if (loom::bench::wants(modes, "throughput")) run_throughput(max_threads, quick);
  if (loom::bench::wants(modes, "error")) run_error(quick);
}
