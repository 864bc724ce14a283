// bench_parameterize [--quick] [--large] [--runs N] [--threads N] [--out DIR] [--help]
// Loom's fixed-boundary maps, every weight, on the course meshes and on
// generated noisy hemispheres of ~100k (and with --large ~1M) faces: wall and
// CPU time (medians), flips and distortion; side by side with CGAL 5.5 (built
// with -DLOOM_WITH_CGAL=ON) on the same boundary UVs, with the largest UV
// difference. CSV and plots go to bench/results.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bench_harness.hpp"
#include "generators.hpp"
#include "harmonic_map.hpp"
#include "loom/numerics/distortion.hpp"
#include "loom/numerics/mesh_topology.hpp"
#include "mesh_codec.hpp"
#ifdef LOOM_BENCH_CGAL
#include "cgal_peer.hpp"
#endif

namespace {

using loom::numerics::BoundaryShape;

struct Input {
  std::string name;
  Eigen::MatrixX3d V;
  Eigen::MatrixX3i F;
};

// A course mesh through the io plugin's reader (assimp).
Input read_obj(const std::string& name, const std::filesystem::path& path) {
  loom::Mesh mesh = loom::io::read_mesh(path);
  return Input{name, mesh.V, mesh.F};
}

// HemisphereMesh's shape with 1% radial noise: segments·(2·rings - 1) faces.
Input hemisphere(const std::string& name, int rings, int segments) {
  std::mt19937_64 rng(7);
  const loom::Mesh m = loom::generate::hemisphere_mesh(1, rings, segments, 0.01, rng);
  return Input{name, m.V, m.F};
}

struct Time {
  double wall = 0, cpu = 0;  // seconds; cpu = process CPU time over all threads
};

// Medians of wall and CPU time over `runs` runs after one warm-up; with
// `once`, a single run and no warm-up (for the 1M mesh).
template <class F>
Time timed(bool once, int runs, const F& f) {
  if (once) runs = 1;
  else f();
  std::vector<double> wall, cpu;
  for (int r = 0; r < runs; ++r) {
    const auto w0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    f();
    cpu.push_back(static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
    wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count());
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t h = v.size() / 2;
    return v.size() % 2 ? v[h] : (v[h - 1] + v[h]) / 2;
  };
  return {median(wall), median(cpu)};
}

// gnuplot reads "_" as a subscript: legends use "-".
std::string label(std::string text) {
  std::replace(text.begin(), text.end(), '_', '-');
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  loom::bench::Cli cli("bench_parameterize",
                       "Loom's fixed-boundary maps (every weight, circle and square) on the course meshes and a "
                       "noisy hemisphere of ~100k faces; with a CGAL build (-DLOOM_WITH_CGAL=ON) also CGAL 5.5 "
                       "(SparseLU and BiCGSTAB) on the same boundary UVs. Writes parameterize.csv, "
                       "parameterize_times.csv and a plot.");
  bool quick = false, large = false;
  int big_runs = 3;  // timed runs on the 100k mesh (medians; more when the machine is loaded)
  cli.quick(quick, "one timed run per case")
      .flag("--large", large, "add the ~1M-face hemisphere (one run each; CGAL needs ~100 s there)")
      .option("--runs", big_runs, "timed runs on the 100k mesh, medians reported (at least 1)")
      .threads();
  cli.parse(argc, argv);
  big_runs = std::max(1, big_runs);
  std::vector<Input> inputs;
  for (const char* name : {"CatHead", "NefertitiFace", "Isis", "Balls", "BunnyHead", "Beetle"}) {
    const auto path = loom::bench::data_file(std::string("meshes/") + name + ".obj");
    if (!path.empty()) inputs.push_back(read_obj(name, path));
  }
  inputs.push_back(hemisphere("hemisphere_100k", 112, 448));
  if (large) inputs.push_back(hemisphere("hemisphere_1M", 354, 1414));

  loom::bench::Csv csv("parameterize", {"mesh", "faces", "boundary", "weights", "impl", "seconds", "cpu_seconds",
                                         "flipped", "angle_mean", "area_mean", "arap_energy", "max_uv_diff"});
  loom::bench::Csv times("parameterize_times", {"mesh", "faces", "method", "seconds"});
  for (const Input& m : inputs) {
    const bool big = m.F.rows() > 50000, huge = m.F.rows() > 500000;
    const int runs = quick ? 1 : big ? big_runs : 5;
    const auto loops = loom::numerics::boundary_loops(m.F);
#ifdef LOOM_BENCH_CGAL
    // CGAL maps the loop's own component; meshes with holes need filling first, which it does not do.
    loom::bench::CgalPeer* peer = loops.size() == 1 ? loom::bench::cgal_build(m.V, m.F) : nullptr;
#endif
    for (BoundaryShape shape : {BoundaryShape::circle, BoundaryShape::square}) {
      if (huge && shape == BoundaryShape::square) continue;
      const std::string bname = shape == BoundaryShape::circle ? "circle" : "square";
      for (size_t w = 0; w < loom::parameterize::weight_names().size(); ++w) {
        const std::string wname = loom::parameterize::weight_names()[w];
        const auto weights = static_cast<loom::parameterize::Weights>(w);
        loom::parameterize::Parameterization p;
        // The square only for flip counts: timings are the circle's.
        const Time t = timed(huge, shape == BoundaryShape::circle ? runs : 1,
                               [&] { p = loom::parameterize::parameterize(m.V, m.F, weights, shape); });
        const auto r = loom::numerics::distortion(m.V, m.F, p.UV);
        csv.row({m.name, static_cast<long long>(m.F.rows()), bname, wname, std::string("loom"), t.wall, t.cpu,
                 static_cast<long long>(r.flipped), r.angle_mean, r.area_mean, r.arap_energy, 0.0});
        if (shape == BoundaryShape::circle)
          times.row({m.name, static_cast<long long>(m.F.rows()), label("loom " + wname), t.wall});
#ifdef LOOM_BENCH_CGAL
        if (!peer || shape != BoundaryShape::circle) continue;
        if (wname != "uniform" && wname != "cotangent" && wname != "mean_value") continue;
        for (const char* solver : {"sparselu", "bicgstab"}) {
          if (huge && std::string(solver) == "bicgstab") continue;  // slower still than SparseLU at 1M
          Eigen::MatrixX2d UV;
          const Time tc = timed(huge, runs, [&] {
            UV = loom::bench::cgal_parameterize(*peer, p.UV, loops[0][0], wname, solver);
          });
          const auto rc = loom::numerics::distortion(m.V, m.F, UV);
          csv.row({m.name, static_cast<long long>(m.F.rows()), bname, wname, std::string("cgal_") + solver,
                   tc.wall, tc.cpu, static_cast<long long>(rc.flipped), rc.angle_mean, rc.area_mean, rc.arap_energy,
                   (UV - p.UV).cwiseAbs().maxCoeff()});
          times.row({m.name, static_cast<long long>(m.F.rows()), label(std::string("cgal_") + solver + " " + wname),
                     tc.wall});
        }
#endif
      }
    }
#ifdef LOOM_BENCH_CGAL
    if (peer) loom::bench::cgal_free(peer);
#endif
  }
  std::cout << "wrote " << csv.save() << " and " << times.save() << "\n";
  loom::bench::plot(times, {"faces", "seconds", "method", "Fixed-boundary maps (circle): Loom vs CGAL 5.5", true, true, ""});
  return 0;
}
