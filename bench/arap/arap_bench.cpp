// ARAP and ASAP: Loom's prefactored local/global solver against CGAL 5.5's
// ARAP_parameterizer_3 (which refactors its matrix every iteration), on the
// course meshes and generated hemispheres of 20k, 100k (and with --large 1M)
// faces. Writes energy-vs-time curves and a summary; --quick runs 20k only.
//
// Energy: E = ½ Σ_t Σ_i cot θ_t^i ‖(u_t^i − u_t^{i+1}) − L_t d_t^i‖² with the
// best rotation L_t per triangle, evaluated by the same code on both results
// (CGAL's printed per-iteration energies use the previous iteration's L_t and
// are shown as its curve).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <random>
#include <sstream>
#include <string>

#include "bench_harness.hpp"
#include "cholmod_limit.hpp"
#include "generators.hpp"
#include "local_global.hpp"
#include "mesh_codec.hpp"
#include "loom/numerics/distortion.hpp"
#include "similarity_map.hpp"
#include "tutte_map.hpp"

#ifdef LOOM_BENCH_CGAL
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_parameterization/ARAP_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/parameterize.h>
#endif

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct Mesh {
  std::string name;
  Eigen::MatrixX3d V;
  Eigen::MatrixX3i F;
};

// A course mesh through the io plugin's reader (assimp).
Mesh load_obj(const std::string& name, const std::string& path) {
  loom::Mesh mesh = loom::io::read_mesh(path);
  return Mesh{name, mesh.V, mesh.F};
}

// A hemisphere cap (the pole to 80° latitude) on the generators' polar grid,
// odd rings turned by half a segment, with radial noise of about a quarter of
// an edge length inside the boundary: about 2·rings·segments faces.
Mesh hemisphere(int rings, int segments) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-0.02, 0.02);
  const loom::Mesh cap = loom::generate::polar_mesh(rings, segments, [&](double t, double phi) {
    if (t == 0) return Eigen::Vector3d(0, 0, 1);
    const int k = static_cast<int>(std::lround(t * rings));
    const double polar = 1.4 * t, azimuth = phi + M_PI * (k % 2) / segments;
    const double r = 1 + (k < rings ? noise(rng) * 16.0 / rings : 0);
    return Eigen::Vector3d(r * std::sin(polar) * std::cos(azimuth), r * std::sin(polar) * std::sin(azimuth),
                           r * std::cos(polar));
  });
  Mesh m{"", cap.V, cap.F};
  m.name = "hemisphere-" + std::to_string(m.F.rows() / 1000) + "k";
  return m;
}

struct Curve {
  std::vector<double> seconds, energy;
};

struct Run {
  Eigen::MatrixX2d UV;
  Curve curve;
  double total = 0;
  double cpu = 0;  // process CPU seconds, all threads: the work, whatever the machine's load
};

double cpu_seconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

// Loom: Tutte init (CGAL starts from mean-value Tutte on one-boundary
// meshes), then ARAP for `iterations` or until an iteration lowers the energy
// by less than `tolerance` of it (0: no early stop).
Run loom_arap(const Mesh& m, int iterations, double tolerance = 0) {
  Run r;
  const auto t0 = Clock::now();
  const double c0 = cpu_seconds();
  const auto sys = loom::arap::arap_system(m.V, m.F, {});
  const Eigen::MatrixX2d UV0 = loom::arap::tutte_map(m.V, m.F);
  loom::arap::ArapOptions o;
  o.max_iterations = iterations;
  o.tolerance = tolerance;
  r.curve.seconds.push_back(since(t0));
  const auto res = loom::arap::arap(sys, UV0, o, [&](int, double E, const Eigen::MatrixX2d&) {
    r.curve.seconds.push_back(since(t0));
    r.curve.energy.push_back(E);
  });
  r.total = since(t0);
  r.cpu = cpu_seconds() - c0;
  r.curve.energy.insert(r.curve.energy.begin(), res.energy.front());
  r.curve.seconds.resize(r.curve.energy.size());
  r.UV = res.UV;
  return r;
}

#ifdef LOOM_BENCH_CGAL
// Timestamps every line CGAL prints in verbose mode, to recover its
// energy-per-iteration curve from one run.
class StampedLines : public std::streambuf {
 public:
  explicit StampedLines(Clock::time_point t0) : t0_(t0) {}
  std::vector<std::pair<double, std::string>> lines;

 protected:
  int overflow(int c) override {
    if (c == '\n') {
      lines.emplace_back(since(t0_), current_);
      current_.clear();
    } else if (c != EOF) {
      current_ += static_cast<char>(c);
    }
    return c;
  }

 private:
  Clock::time_point t0_;
  std::string current_;
};

using Kernel = CGAL::Simple_cartesian<double>;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;

Run cgal_arap(const Mesh& m, double lambda, int iterations, double tolerance) {
  namespace SMP = CGAL::Surface_mesh_parameterization;
  SurfaceMesh sm;
  std::vector<SurfaceMesh::Vertex_index> vid;
  for (Eigen::Index v = 0; v < m.V.rows(); ++v) vid.push_back(sm.add_vertex({m.V(v, 0), m.V(v, 1), m.V(v, 2)}));
  for (Eigen::Index t = 0; t < m.F.rows(); ++t) sm.add_face(vid[m.F(t, 0)], vid[m.F(t, 1)], vid[m.F(t, 2)]);
  auto uvmap = sm.add_property_map<SurfaceMesh::Vertex_index, Kernel::Point_2>("v:uv").first;
  const auto bhd = CGAL::Polygon_mesh_processing::longest_border(sm).first;
  using Parameterizer = SMP::ARAP_parameterizer_3<SurfaceMesh>;
  Parameterizer p(Parameterizer::Border_parameterizer(), Parameterizer::Solver_traits(), lambda,
                  iterations, tolerance);
  Run r;
  const auto t0 = Clock::now();
  const double c0 = cpu_seconds();
  StampedLines sink(t0);
  std::streambuf* old = std::cout.rdbuf(&sink);
  const auto status = SMP::parameterize(sm, p, bhd, uvmap);
  r.total = since(t0);
  r.cpu = cpu_seconds() - c0;
  std::cout.rdbuf(old);
  if (status != SMP::OK) std::fprintf(stderr, "CGAL failed on %s: %s\n", m.name.c_str(), SMP::get_error_message(status));
  for (const auto& [t, line] : sink.lines) {
    double E;
    if (std::sscanf(line.c_str(), "Initial energy: %lf", &E) == 1 ||
        std::sscanf(line.c_str(), "Energy at iteration %*d : %lf", &E) == 1) {
      r.curve.seconds.push_back(t);
      r.curve.energy.push_back(E);
    }
  }
  r.UV.resize(m.V.rows(), 2);
  for (Eigen::Index v = 0; v < m.V.rows(); ++v) r.UV.row(v) << uvmap[vid[v]].x(), uvmap[vid[v]].y();
  return r;
}
#endif

#ifdef LOOM_BENCH_CGAL
// Where Loom's ARAP time goes (wall medians of 3): the system (frames,
// matrix, factorization), the Tutte start, `iterations` iterations; beside
// CHOLMOD alone on K_ff with each ordering (README's benchmark table: the
// direct limit is the best factorization plus `iterations` solves).
void arap_stages_and_limit(const Mesh& m, long long iterations, loom::bench::Csv& out) {
  const auto stage = [&](const std::string& name, const std::function<void()>& f) {
    out.row({m.name, name, std::string("-"), 1LL, loom::bench::time_median(f, 3).median, 0.0, 0.0,
             loom::bench::load_average()});
  };
  loom::arap::ArapSystem sys;
  Eigen::MatrixX2d UV0;
  stage("triangle frames", [&] { loom::arap::triangle_frames(m.V, m.F); });
  stage("system (frames, K, factorization)", [&] { sys = loom::arap::arap_system(m.V, m.F, {}); });
  stage("tutte start", [&] { UV0 = loom::arap::tutte_map(m.V, m.F); });
  loom::arap::ArapOptions o;
  o.max_iterations = static_cast<int>(iterations);
  o.tolerance = 0;
  stage("iterations", [&] { loom::arap::arap(sys, UV0, o); });
  for (const auto& t : loom::bench::cholmod_orderings(sys.K, 2, 3))
    for (const auto& [part, seconds] : {std::pair<const char*, double>{"cholmod analyze", t.analyze},
                                        {"cholmod factor", t.factor}, {"cholmod solve", t.solve}})
      out.row({m.name, std::string(part), t.ordering, (long long)t.blas_threads, seconds, t.factor_nonzeros, t.flops,
               loom::bench::load_average()});
}
#endif

}  // namespace

int main(int argc, char** argv) {
  loom::bench::Cli cli("bench_arap",
                       "ASAP and ARAP against CGAL's ARAP_parameterizer_3 (when built with -DLOOM_WITH_CGAL=ON) "
                       "on the course meshes and hemispheres of 20k and 100k faces: energy against time, "
                       "iterations to CGAL's energy, flips.");
  bool quick = false, large = false, generated_only = false;
  std::string meshes_dir;
  cli.quick(quick, "the 20k-face hemisphere only")
      .flag("--large", large, "add the 1M-face hemisphere (Loom only)")
      .flag("--generated", generated_only, "only the generated hemispheres (not the course meshes)")
      .option("--write-meshes", meshes_dir,
              "write the generated hemispheres as OBJ files into this folder (hemisphere-20k.obj, ...) and stop: "
              "bench_cold runs `loom run` on them")
      .threads();
  cli.parse(argc, argv);
  if (!meshes_dir.empty()) {
    for (const Mesh& m : {hemisphere(50, 200), hemisphere(112, 448)}) {
      loom::Mesh out;
      out.V = m.V;
      out.F = m.F;
      loom::io::write_mesh(out, std::filesystem::path(meshes_dir) / (m.name + ".obj"), "");
    }
    return 0;
  }
  std::vector<Mesh> meshes;
  if (!quick && !generated_only)
    for (const char* name : {"Balls", "BunnyHead", "CatHead", "NefertitiFace", "Isis"}) {
      const auto path = loom::bench::data_file(std::string("meshes/") + name + ".obj");
      if (!path.empty()) meshes.push_back(load_obj(name, path.string()));
    }
  meshes.push_back(hemisphere(50, 200));
  if (!quick) meshes.push_back(hemisphere(112, 448));
  if (large) meshes.push_back(hemisphere(354, 1414));

  loom::bench::Csv curve("arap_curve", {"mesh", "method", "iteration", "seconds", "energy"});
  loom::bench::Csv limit("arap_limit", {"mesh", "part", "ordering", "blas_threads", "seconds", "factor_nonzeros",
                                        "flops", "load_average"});
  loom::bench::Csv summary("arap", {"mesh", "faces", "method", "seconds", "cpu_seconds", "energy",
                                    "flips", "iterations", "speedup"});
  const int iterations = 100;
  std::map<std::string, double> reference;  // the lowest final energy per mesh
  for (const Mesh& m : meshes) {
    const auto frames = loom::arap::triangle_frames(m.V, m.F);
    auto energy = [&](const Eigen::MatrixX2d& UV) { return loom::arap::local_global_energy(frames, m.F, UV); };
    auto flips = [&](const Eigen::MatrixX2d& UV) { return loom::numerics::distortion(m.V, m.F, UV).flipped; };
    const long long faces = m.F.rows();

    // Loom ARAP: median of 3 runs for the 100-iteration time.
    std::vector<Run> runs;
    std::vector<double> totals, cpus;
    for (int k = 0; k < 3; ++k) {
      runs.push_back(loom_arap(m, iterations));
      totals.push_back(runs.back().total);
      cpus.push_back(runs.back().cpu);
    }
    const Run& ours = runs.back();
    reference[m.name] = energy(ours.UV);
    std::sort(totals.begin(), totals.end());
    std::sort(cpus.begin(), cpus.end());
    for (size_t k = 0; k < ours.curve.energy.size(); ++k)
      curve.row({m.name, "loom ARAP", (long long)k, ours.curve.seconds[k], ours.curve.energy[k]});

    // Loom ASAP: one solve.
    Eigen::MatrixX2d asap_uv;
    const auto asap_t = loom::bench::time_median([&] {
      asap_uv = loom::arap::similarity_map(loom::arap::triangle_frames(m.V, m.F), m.F, int(m.V.rows()),
                                           loom::arap::similarity_pins(m.V, m.F, {})).UV;
    }, 3);
    // The similarity energy scales with the square of the map's size and the
    // two ASAPs pin different sizes: compare it at the mesh's own area.
    auto scale_free = [&](const Eigen::MatrixX2d& UV) {
      double uv_area = 0;
      for (Eigen::Index t = 0; t < m.F.rows(); ++t) {
        const Eigen::RowVector2d a = UV.row(m.F(t, 1)) - UV.row(m.F(t, 0)), b = UV.row(m.F(t, 2)) - UV.row(m.F(t, 0));
        uv_area += std::abs(a.x() * b.y() - a.y() * b.x()) / 2;
      }
      return loom::arap::local_global_energy(frames, m.F, UV, 0) * frames.area.sum() / uv_area;
    };
    const double asap_energy = scale_free(asap_uv);
    summary.row({m.name, faces, "loom ASAP", asap_t.median, "", asap_energy, (long long)flips(asap_uv), "", ""});

    summary.row({m.name, faces, "loom ARAP 100 iterations", totals[1], cpus[1], energy(ours.UV),
                 (long long)flips(ours.UV), (long long)iterations, ""});

#ifdef LOOM_BENCH_CGAL
    if (faces > 500000) continue;  // CGAL would take many minutes: Loom alone at 1M faces
    // CGAL's time: to its last iteration, leaving out the MVC post-processing
    // it runs when the result has flips.
    const Run cgal = cgal_arap(m, 1e8, 50, 1e-6);
    const double cgal_energy = energy(cgal.UV), cgal_time = cgal.curve.seconds.back();
    for (size_t k = 0; k < cgal.curve.energy.size(); ++k)
      curve.row({m.name, "CGAL ARAP", (long long)k, cgal.curve.seconds[k], cgal.curve.energy[k]});
    summary.row({m.name, faces, "CGAL ARAP (lambda 1e8)", cgal_time, cgal.cpu, cgal_energy,
                 (long long)flips(cgal.UV), (long long)cgal.curve.energy.size() - 1, ""});
    reference[m.name] = std::min(reference[m.name], cgal_energy);
    if (faces > 50000) {
      // The node's own stopping rule (its default tolerance) against CGAL's
      // default run, alternating round by round so that load falls on both.
      const loom::arap::ArapOptions defaults;
      std::vector<double> ours_t, cgal_t;
      double ours_energy = 0;
      long long ours_iterations = 0;
      for (int round = 0; round < 3; ++round) {
        const Run a = loom_arap(m, defaults.max_iterations, defaults.tolerance);
        ours_t.push_back(a.total);
        ours_energy = energy(a.UV);
        ours_iterations = (long long)a.curve.energy.size() - 1;
        cgal_t.push_back(cgal_arap(m, 1e8, 50, 1e-6).curve.seconds.back());
      }
      std::sort(ours_t.begin(), ours_t.end());
      std::sort(cgal_t.begin(), cgal_t.end());
      summary.row({m.name, faces, "loom ARAP to its tolerance (alternating)", ours_t[1], "", ours_energy, "",
                   ours_iterations, cgal_t[1] / ours_t[1]});
      summary.row({m.name, faces, "CGAL ARAP (alternating)", cgal_t[1], "", cgal_energy, "", "", ""});
      arap_stages_and_limit(m, ours_iterations, limit);
    }
    // Median over the three runs of the time to reach CGAL's final energy.
    std::vector<std::pair<double, size_t>> reach;
    for (const Run& r : runs)
      for (size_t k = 0; k < r.curve.energy.size(); ++k)
        if (r.curve.energy[k] <= cgal_energy * (1 + 1e-9)) {
          reach.emplace_back(r.curve.seconds[k], k);
          break;
        }
    if (reach.size() == runs.size()) {
      std::sort(reach.begin(), reach.end());
      const auto [t, k] = reach[reach.size() / 2];
      summary.row({m.name, faces, "loom ARAP to CGAL's energy", t, "", ours.curve.energy[k], "",
                   (long long)k, cgal_time / t});
    }
    if (faces < 50000) {  // CGAL's iterative ASAP takes minutes beyond
      const Run cgal_asap = cgal_arap(m, 0, 50, 1e-6);
      summary.row({m.name, faces, "CGAL ASAP (lambda 0)", cgal_asap.curve.seconds.back(), cgal_asap.cpu,
                   scale_free(cgal_asap.UV), (long long)flips(cgal_asap.UV),
                   (long long)cgal_asap.curve.energy.size() - 1,
                   cgal_asap.curve.seconds.back() / asap_t.median});
    }
#endif
  }
  curve.save();
  summary.save();
  limit.save();
  // Plots: the energy above the lowest final energy (both evaluated by
  // local_global_energy), relative, on a log scale, floored at 1e-7: CGAL's printed
  // energies use its own cotangents (CGAL::Weights::cotangent), which differ
  // from ours at about that level. CGAL's initial energy is left out: it
  // includes λ (a²+b²−1)² of its mean-value start, about 1e12 for λ = 1e8.
  for (const Mesh& m : meshes) {
    if (m.name.rfind("hemisphere", 0) != 0) continue;
    const double lowest = reference[m.name];
    loom::bench::Csv one("arap_curve_" + m.name, {"method", "seconds", "excess"});
    for (const auto& row : curve.rows()) {
      if (std::get<std::string>(row[0]) != m.name) continue;
      if (std::get<std::string>(row[1]) == "CGAL ARAP" && std::get<long long>(row[2]) == 0) continue;
      one.row({row[1], row[3], std::max(1e-7, (std::get<double>(row[4]) - lowest) / lowest)});
    }
    one.save();
    loom::bench::plot(one, {"seconds", "excess", "method",
                            "ARAP energy above the final, relative, against time: " + m.name, false,
                            true, ""});
  }
  return 0;
}
