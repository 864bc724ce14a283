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
#include <functional>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "alternating.hpp"
#include "bench_harness.hpp"
#include "cholmod_limit.hpp"
#include "loom/numerics/blas_threads.hpp"
#include "generators.hpp"
#include "harmonic_map.hpp"
#include "loom/numerics/boundary_map.hpp"
#include "loom/numerics/distortion.hpp"
#include "loom/numerics/fixed_boundary.hpp"
#include "loom/numerics/sparse_solver.hpp"
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

// gnuplot reads "_" as a subscript: legends use "-".
std::string label(std::string text) {
  std::replace(text.begin(), text.end(), '_', '-');
  return text;
}

// Where the uniform (Tutte) map's time goes on a mesh, stage by stage (wall
// medians), beside what CHOLMOD alone needs for the same matrix with each
// ordering: the limit of a direct solve (README's benchmark table).
void stages_and_limit(const Input& m, int runs, loom::bench::Csv& out) {
  using namespace loom::numerics;
  const auto stage = [&](const std::string& name, const std::function<void()>& f) {
    out.row({m.name, name, std::string("-"), 1LL, loom::bench::time_median(f, runs).median, 0.0, 0.0,
             loom::bench::load_average()});
  };
  std::vector<std::vector<int>> loops;
  Eigen::MatrixX2d circle;
  SparseMatrix W;
  FixedBoundarySystem sys;
  SparseCholesky chol;
  const auto tutte = [&] {
    loom::parameterize::parameterize(m.V, m.F, loom::parameterize::Weights::uniform, BoundaryShape::circle);
  };
  stage("loom total", tutte);
  // What OPENBLAS_NUM_THREADS=2 would give a user on an idle machine.
  if (loom::numerics::set_blas_threads(2)) {
    stage("loom total, 2 BLAS threads", tutte);
    loom::numerics::set_blas_threads(1);
  }
  stage("boundary loops", [&] { loops = boundary_loops(m.F); });
  stage("boundary on the circle", [&] { circle = map_boundary(m.V, m.F, loops[0], BoundaryShape::circle); });
  stage("uniform weights", [&] { W = loom::parameterize::weight_matrix(m.V, m.F, loom::parameterize::Weights::uniform); });
  Eigen::MatrixXd X0 = Eigen::MatrixXd::Zero(m.V.rows(), 2);
  for (size_t k = 0; k < loops[0].size(); ++k) X0.row(loops[0][k]) = circle.row(static_cast<Eigen::Index>(k));
  stage("system assembly", [&] { sys = fixed_boundary_system(W, m.F, loops[0], X0); });
  stage("cholmod analyze + factor (loom)", [&] { chol.compute(sys.A); });
  stage("cholmod solve (loom)", [&] { chol.solve(sys.B); });
  for (const auto& t : loom::bench::cholmod_orderings(sys.A, 2, runs)) {
    out.row({m.name, std::string("cholmod analyze"), t.ordering, (long long)t.blas_threads, t.analyze,
             t.factor_nonzeros, t.flops, loom::bench::load_average()});
    out.row({m.name, std::string("cholmod factor"), t.ordering, (long long)t.blas_threads, t.factor, t.factor_nonzeros,
             t.flops, loom::bench::load_average()});
    out.row({m.name, std::string("cholmod solve"), t.ordering, (long long)t.blas_threads, t.solve, t.factor_nonzeros,
             t.flops, loom::bench::load_average()});
  }
}

}  // namespace

int main(int argc, char** argv) {
  loom::bench::Cli cli("bench_parameterize",
                       "Loom's fixed-boundary maps (every weight, circle and square) on the course meshes and a "
                       "noisy hemisphere of ~100k faces; with a CGAL build (-DLOOM_WITH_CGAL=ON) also CGAL 5.5 "
                       "(SparseLU and BiCGSTAB) on the same boundary UVs. Writes parameterize.csv, "
                       "parameterize_times.csv and a plot.");
  bool quick = false, large = false, generated_only = false, uniform_only = false;
  int big_runs = 3;  // timed runs on the 100k mesh (medians; more when the machine is loaded)
  cli.quick(quick, "one timed run per case")
      .flag("--large", large, "add the ~1M-face hemisphere (one run each; CGAL needs ~100 s there)")
      .flag("--generated", generated_only, "only the generated hemispheres (not the course meshes)")
      .flag("--uniform", uniform_only, "only the uniform (Tutte) weights")
      .option("--runs", big_runs, "timed runs on the 100k mesh, medians reported (at least 1)")
      .threads();
  cli.parse(argc, argv);
  big_runs = std::max(1, big_runs);
  std::vector<Input> inputs;
  for (const char* name : {"CatHead", "NefertitiFace", "Isis", "Balls", "BunnyHead", "Beetle"}) {
    const auto path = loom::bench::data_file(std::string("meshes/") + name + ".obj");
    if (!path.empty() && !generated_only) inputs.push_back(read_obj(name, path));
  }
  inputs.push_back(hemisphere("hemisphere_100k", 112, 448));
  if (large) inputs.push_back(hemisphere("hemisphere_1M", 354, 1414));

  loom::bench::Csv csv("parameterize", {"mesh", "faces", "boundary", "weights", "impl", "seconds", "cpu_seconds",
                                         "flipped", "angle_mean", "area_mean", "arap_energy", "max_uv_diff",
                                         "load_average"});
  loom::bench::Csv times("parameterize_times", {"mesh", "faces", "method", "seconds"});
  loom::bench::Csv limit("parameterize_limit", {"mesh", "part", "ordering", "blas_threads", "seconds",
                                                "factor_nonzeros", "flops", "load_average"});
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
        if (uniform_only && wname != "uniform") continue;
        const auto weights = static_cast<loom::parameterize::Weights>(w);
        loom::parameterize::Parameterization p;
        std::vector<std::string> names = {"loom"};
        std::vector<std::function<void()>> contenders = {
            [&] { p = loom::parameterize::parameterize(m.V, m.F, weights, shape); }};
        p = loom::parameterize::parameterize(m.V, m.F, weights, shape);  // the border UVs CGAL is given
#ifdef LOOM_BENCH_CGAL
        std::vector<Eigen::MatrixX2d> cgal_uv(2);
        const char* solvers[2] = {"sparselu", "bicgstab"};
        const bool with_peer = peer && shape == BoundaryShape::circle &&
                               (wname == "uniform" || wname == "cotangent" || wname == "mean_value");
        const Eigen::MatrixX2d border_uv = p.UV;
        for (int k = 0; with_peer && k < 2; ++k)
          if (!(huge && k == 1))  // BiCGSTAB is slower still than SparseLU at 1M
            names.push_back(std::string("cgal_") + solvers[k]), contenders.emplace_back([&, k] {
              cgal_uv[k] = loom::bench::cgal_parameterize(*peer, border_uv, loops[0][0], wname, solvers[k]);
            });
#endif
        // Loom and its peers alternate run by run, so a change in the
        // machine's load falls on all of them. The square only for flip
        // counts: timings are the circle's.
        const auto t = loom::bench::time_alternating(huge || shape != BoundaryShape::circle ? 1 : runs,
                                                     contenders, !huge);
        const auto r = loom::numerics::distortion(m.V, m.F, p.UV);
        csv.row({m.name, static_cast<long long>(m.F.rows()), bname, wname, std::string("loom"), t[0].wall,
                 t[0].cpu, static_cast<long long>(r.flipped), r.angle_mean, r.area_mean, r.arap_energy, 0.0,
                 loom::bench::load_average()});
        if (shape == BoundaryShape::circle)
          times.row({m.name, static_cast<long long>(m.F.rows()), label("loom " + wname), t[0].wall});
#ifdef LOOM_BENCH_CGAL
        for (std::size_t k = 1; k < contenders.size(); ++k) {
          const Eigen::MatrixX2d& UV = cgal_uv[k - 1];
          const auto rc = loom::numerics::distortion(m.V, m.F, UV);
          csv.row({m.name, static_cast<long long>(m.F.rows()), bname, wname, names[k], t[k].wall,
                   t[k].cpu, static_cast<long long>(rc.flipped), rc.angle_mean, rc.area_mean, rc.arap_energy,
                   (UV - p.UV).cwiseAbs().maxCoeff(), loom::bench::load_average()});
          times.row({m.name, static_cast<long long>(m.F.rows()), label(names[k] + " " + wname),
                     t[k].wall});
        }
#endif
      }
    }
#ifdef LOOM_BENCH_CGAL
    if (peer) loom::bench::cgal_free(peer);
#endif
    if (big && !huge) stages_and_limit(m, runs, limit);
  }
  csv.save();
  times.save();
  limit.save();
  loom::bench::plot(times, {"faces", "seconds", "method", "Fixed-boundary maps (circle): Loom vs CGAL 5.5", true, true, ""});
  return 0;
}
