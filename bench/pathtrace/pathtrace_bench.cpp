// bench_pathtrace: the path tracer's time-vs-error figures.
//   embree       Embree's tutorial path tracer (embree-tools) on its cornell_box model,
//                side by side: mean pixel values, paths/s at 512², 1 and 2 threads,
//                relMSE and efficiency 1 / (relMSE × time) against a reference
//   convergence  relMSE against spp 4..1024 on the Cornell box, fitted slope
//   strategies   equal-time relMSE of BSDF-only, NEE-only and MIS (Cornell box, night scene)
//   environment  a map with one bright pixel: importance vs uniform sampling, MIS vs not
//   adaptive     relMSE against time, adaptive thresholds vs uniform spp
//   bvh          BVH build time of a 1M-triangle mesh
//   cycles       Blender's Cycles side by side (cycles_peer.hpp)
//   rays         Embree's own ray rate on the rays PathTrace casts, the limit, and the
//                same for Embree's tutorial path tracer on its rays (ray_rate.hpp)
// relMSE = mean over pixels and channels of (x - ref)² / (ref² + 0.01).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <set>

#include <tbb/global_control.h>

#include "bench_harness.hpp"
#include "cornell_box_scene.hpp"
#include "cycles_peer.hpp"
#include "embree_scene.hpp"
#include "embree_tutorial.hpp"
#include "image_error.hpp"
#include "integrator.hpp"
#include "lanes.hpp"
#include "ray_rate.hpp"
#include "scenes.hpp"
#include "sphere_mesh.hpp"

namespace fs = std::filesystem;
using namespace loom::pathtrace;
using loom::bench::Csv;
using loom::bench::median;
using loom::bench::process_cpu_seconds;
using loom::pathtrace::bench::read_pfm;
using loom::pathtrace::bench::rel_mse;
using loom::pathtrace::bench::run_embree_tutorial;
using loom::pathtrace::bench::save_png;

namespace {

// --quick: a quarter of the reference samples and of the 512² repetitions.
bool quick = false;
int ref_spp(int spp) { return quick ? spp / 4 : spp; }

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

cv::Mat clamp01(const cv::Mat& m) {
  cv::Mat c = cv::max(m, 0.0);
  return cv::min(c, 1.0);
}
// As Embree's tutorial framebuffer stores it: clamped to [0, 1], 8 bits, truncated.
cv::Mat quantize8(const cv::Mat& m) {
  cv::Mat c = clamp01(m), out;
  c.convertTo(out, CV_32F, 255.0);
  out.forEach<cv::Vec3f>([](cv::Vec3f& p, const int*) {
    for (int i = 0; i < 3; ++i) p[i] = std::floor(p[i]) / 255.f;
  });
  return out;
}

struct Timed {
  RenderResult result;
  double seconds;      // wall
  double cpu_seconds;  // user + system over all threads: steadier on a shared machine
};
Timed timed_render(const loom::Scene& scene, const EmbreeScene& traced, const RenderSettings& s) {
  const auto t = std::chrono::steady_clock::now();
  const double c0 = process_cpu_seconds();
  RenderResult r = render(scene, *scene.camera, traced, s);
  return {std::move(r), seconds_since(t), process_cpu_seconds() - c0};
}

// Loom alone on the embree comparison scene, 1 thread: paths per CPU second
// and rays per path with each sampler, alternating, medians of 3 (for
// profiling: `perf record build/bin/bench_pathtrace throughput`).
void bench_throughput() {
  const loom::Scene scene = bench::embree_cornell_box(EMBREE_MODELS);
  const EmbreeScene traced(scene);
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
  RenderSettings s;
  s.width = s.height = 512;
  s.spp = quick ? 4 : 16;
  s.max_depth = 8;
  s.russian_roulette = false;
  std::map<std::string, std::vector<double>> rate;
  double rays_per_path = 0;
  for (int rep = 0; rep < 3; ++rep)
    for (const auto& [name, kind] : {std::pair<std::string, SamplerKind>{"sobol", SamplerKind::sobol},
                                     {"independent", SamplerKind::independent}}) {
      s.sampler = kind;
      const Timed t = timed_render(scene, traced, s);
      rate[name].push_back(double(t.result.paths) / t.cpu_seconds);
      rays_per_path = double(t.result.rays) / double(t.result.paths);
    }
  for (auto& [name, r] : rate) {
    std::sort(r.begin(), r.end());
    std::cout << "throughput (1 thread, 512^2, " << s.spp << " spp, depth 8, " << name << " sampler): " << r[1] / 1e6
              << " M paths per CPU s (median of 3), " << rays_per_path << " rays per path\n";
  }
  std::cout << "load " << loom::bench::load_average() << "\n";
}

// ---- Embree's tutorial path tracer --------------------------------------------------

void bench_embree() {
  if (!bench::embree_tutorial_installed()) {
    std::cout << "embree: Embree's pathtracer (embree-tools) is not installed: skipped\n";
    return;
  }
  const loom::Scene scene = bench::embree_cornell_box(EMBREE_MODELS);
  const EmbreeScene traced(scene);
  const fs::path tmp = bench::tutorial_scratch(".pfm");
  Csv csv("pathtrace_embree",
          {"renderer", "threads", "size", "spp", "seconds", "cpu_seconds", "paths_per_s", "paths_per_cpu_s",
           "rays_per_s", "mean_r", "mean_g", "mean_b", "relmse", "efficiency_cpu", "load1"});
  // Throughput at 512², depth 8, runs interleaved (loom, embree, loom, ...).
  // The machine is shared: besides wall time, CPU time (user + system, all
  // threads) is measured, for Loom around render(), for Embree as its child
  // process's; Embree's is its marginal cost per sample, (t(spp) - t(1))
  // scaled to spp, so loading the model and building its BVH cancel.
  const int size = 512, spp = 16, depth = 8;
  for (int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    RenderSettings s;
    s.width = s.height = size;
    s.spp = spp;
    s.max_depth = depth;
    s.russian_roulette = false;  // Embree's tutorial has none: same path lengths
    std::vector<double> wall_ours, cpu_ours, wall_embree, cpu_embree;
    Timed ours{};
    for (int rep = 0; rep < (quick ? 1 : 3); ++rep) {
      ours = timed_render(scene, traced, s);
      cpu_ours.push_back(ours.cpu_seconds);
      wall_ours.push_back(ours.seconds);
      const bench::TutorialSeconds embree = bench::time_embree_tutorial(size, spp, depth, threads, tmp);
      wall_embree.push_back(embree.wall);
      cpu_embree.push_back(embree.cpu);
    }
    const double paths = double(size) * size * spp;
    const cv::Scalar m = cv::mean(quantize8(ours.result.image));
    const double rays_per_path = double(ours.result.rays) / paths;
    csv.row({"loom", (long long)threads, (long long)size, (long long)spp, median(wall_ours), median(cpu_ours),
             paths / median(wall_ours), paths / median(cpu_ours), rays_per_path * paths / median(wall_ours), m[0], m[1],
             m[2], std::string(""), std::string(""), loom::bench::load_average()});
    run_embree_tutorial(size, spp, depth, threads, tmp);
    const cv::Mat e = read_pfm(tmp);
    const cv::Scalar me = e.empty() ? cv::Scalar() : cv::mean(e);
    csv.row({"embree-pathtracer", (long long)threads, (long long)size, (long long)spp, median(wall_embree),
             median(cpu_embree), paths / median(wall_embree), paths / median(cpu_embree), std::string("n/a"), me[0],
             me[1], me[2], std::string(""), std::string(""), loom::bench::load_average()});
  }
  // Error and efficiency at 256², 16 spp, 2 threads, against Loom's 1024-spp
  // image (clamped and 8-bit as Embree writes its output).
  {
    const int n = 256;
    RenderSettings s;
    s.width = s.height = n;
    s.max_depth = depth;
    s.russian_roulette = false;
    s.spp = ref_spp(1024);
    s.seed = 99;
    const cv::Mat reference = clamp01(timed_render(scene, traced, s).result.image);
    save_png(reference, "embree-scene-loom-reference.png");
    s.spp = spp;
    s.seed = 1;
    const Timed ours = timed_render(scene, traced, s);
    const double cpu_ours = ours.cpu_seconds;
    const cv::Mat oq = quantize8(ours.result.image);
    const double e_ours = rel_mse(oq, reference);
    cv::Scalar m = cv::mean(oq);
    csv.row({"loom", 2LL, (long long)n, (long long)spp, ours.seconds, cpu_ours, n * n * spp / ours.seconds,
             n * n * spp / cpu_ours, double(ours.result.rays) / ours.seconds, m[0], m[1], m[2], e_ours,
             1 / (e_ours * cpu_ours), loom::bench::load_average()});
    const bench::TutorialSeconds embree = bench::time_embree_tutorial(n, spp, depth, 2, tmp);
    run_embree_tutorial(n, spp, depth, 2, tmp);
    const double t_embree = embree.wall, c_embree = embree.cpu;
    cv::Mat e = read_pfm(tmp);
    // Embree's camera is left-handed here: its image is the mirror of ours.
    cv::Mat flipped;
    cv::flip(e, flipped, 1);
    const double err_direct = rel_mse(e, reference), err_flipped = rel_mse(flipped, reference);
    const cv::Mat& matched = err_flipped < err_direct ? flipped : e;
    save_png(matched, "embree-scene-embree-16spp.png");
    save_png(oq, "embree-scene-loom-16spp.png");
    const double e_embree = std::min(err_direct, err_flipped);
    m = cv::mean(matched);
    csv.row({"embree-pathtracer", 2LL, (long long)n, (long long)spp, t_embree, c_embree, n * n * spp / t_embree,
             n * n * spp / c_embree, std::string("n/a"), m[0], m[1], m[2], e_embree, 1 / (e_embree * c_embree),
             loom::bench::load_average()});
    std::cout << "embree image matched " << (err_flipped < err_direct ? "mirrored" : "as is") << "\n";
  }
  csv.save();
  std::error_code ignored;
  fs::remove(tmp, ignored);
}

// ---- convergence ---------------------------------------------------------------------

void bench_convergence() {
  CornellBoxOptions o;
  const loom::Scene scene = cornell_box(o);
  const EmbreeScene traced(scene);
  RenderSettings s;
  s.width = s.height = 64;
  // Reference: two independent halves; their difference measures the
  // reference's own noise, which is subtracted from each relMSE.
  s.spp = ref_spp(4096);
  s.seed = 1001;
  const cv::Mat a = timed_render(scene, traced, s).result.image;
  s.seed = 1002;
  const cv::Mat b = timed_render(scene, traced, s).result.image;
  const cv::Mat reference = (a + b) / 2;
  const double ref_noise = rel_mse(a, b) / 4;
  Csv csv("pathtrace_convergence", {"spp", "seconds", "cpu_seconds", "relmse", "relmse_corrected", "load1"});
  std::vector<double> lx, ly;
  for (int spp : {4, 16, 64, 256, 1024}) {
    s.spp = spp;
    s.seed = 7;
    const Timed t = timed_render(scene, traced, s);
    const double e = rel_mse(t.result.image, reference);
    csv.row({(long long)spp, t.seconds, t.cpu_seconds, e, e - ref_noise, loom::bench::load_average()});
    lx.push_back(std::log(double(spp)));
    ly.push_back(std::log(e - ref_noise));
  }
  const double n = double(lx.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < lx.size(); ++i) {
    sx += lx[i];
    sy += ly[i];
    sxx += lx[i] * lx[i];
    sxy += lx[i] * ly[i];
  }
  const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  std::cout << "convergence: fitted slope of log relMSE against log spp = " << slope << " (reference noise "
            << ref_noise << ")\n";
  csv.row(
      {std::string("slope"), slope, std::string(""), std::string(""), std::string(""), loom::bench::load_average()});
  csv.save();
  loom::bench::plot(csv, {"spp", "relmse_corrected", "", "Cornell box: relMSE against spp (MIS)", true, true, ""});
}

// ---- strategies (equal time) --------------------------------------------------------------

void strategies(const std::string& name, const loom::Scene& scene, int size) {
  const EmbreeScene traced(scene);
  RenderSettings s;
  s.width = s.height = size;
  s.spp = ref_spp(1024);
  s.seed = 4242;
  const cv::Mat reference = timed_render(scene, traced, s).result.image;
  Csv csv("pathtrace_strategies_" + name, {"strategy", "spp", "seconds", "cpu_seconds", "relmse", "load1"});
  const std::pair<const char*, Strategy> list[] = {
      {"bsdf", Strategy::bsdf}, {"nee", Strategy::nee}, {"mis", Strategy::mis}};
  for (const auto& [label, strategy] : list)
    for (int spp : {1, 2, 4, 8, 16, 32, 64}) {
      s.spp = spp;
      s.seed = 5;
      s.strategy = strategy;
      const Timed t = timed_render(scene, traced, s);
      csv.row({std::string(label), (long long)spp, t.seconds, t.cpu_seconds, rel_mse(t.result.image, reference),
               loom::bench::load_average()});
      if (spp == 2) save_png(t.result.image, name + "-2spp-" + label + ".png");
    }
  save_png(reference, name + "-reference.png");
  csv.save();
  loom::bench::plot(csv, {"cpu_seconds", "relmse", "strategy", name + ": relMSE against CPU time", true, true, ""});
}

// ---- environment map with one bright pixel -------------------------------------------------

void bench_environment() {
  const loom::Scene scene = bench::bright_pixel_scene();
  const EmbreeScene traced(scene);
  RenderSettings s;
  s.width = s.height = 96;
  s.spp = ref_spp(2048);
  s.seed = 77;
  const cv::Mat reference = timed_render(scene, traced, s).result.image;
  save_png(reference, "bright-pixel-reference.png");
  Csv csv("pathtrace_environment",
          {"method", "spp", "seconds", "cpu_seconds", "relmse", "relmse_ratio_to_mis", "load1"});
  struct Method {
    const char* name;
    Strategy strategy;
    EnvironmentLight::Sampling sampling;
  };
  const Method methods[] = {{"importance+mis", Strategy::mis, EnvironmentLight::Sampling::importance},
                            {"importance-nee-only", Strategy::nee, EnvironmentLight::Sampling::importance},
                            {"uniform+mis", Strategy::mis, EnvironmentLight::Sampling::uniform},
                            {"bsdf-only", Strategy::bsdf, EnvironmentLight::Sampling::importance}};
  double base = 0;
  for (const Method& m : methods) {
    s.spp = 16;
    s.seed = 3;
    s.strategy = m.strategy;
    s.environment_sampling = m.sampling;
    const Timed t = timed_render(scene, traced, s);
    const double e = rel_mse(t.result.image, reference);
    if (base == 0) base = e;
    csv.row({std::string(m.name), 16LL, t.seconds, t.cpu_seconds, e, e / base, loom::bench::load_average()});
    save_png(t.result.image, std::string("bright-pixel-16spp-") + m.name + ".png");
  }
  csv.save();
}

// ---- adaptive sampling ----------------------------------------------------------------------

void bench_adaptive() {
  CornellBoxOptions o;
  o.contents = CornellContents::spheres;
  const loom::Scene scene = cornell_box(o);
  const EmbreeScene traced(scene);
  RenderSettings s;
  s.width = s.height = 96;
  s.max_depth = 12;
  s.spp = ref_spp(2048);
  s.seed = 31;
  const cv::Mat reference = timed_render(scene, traced, s).result.image;
  Csv csv("pathtrace_adaptive", {"method", "parameter", "mean_spp", "seconds", "cpu_seconds", "relmse", "load1"});
  for (int spp : {16, 32, 64, 128, 256}) {
    s.spp = spp;
    s.seed = 8;
    s.adaptive_threshold = 0;
    const Timed t = timed_render(scene, traced, s);
    csv.row({std::string("uniform"), double(spp), t.result.mean_spp, t.seconds, t.cpu_seconds,
             rel_mse(t.result.image, reference), loom::bench::load_average()});
  }
  for (double threshold : {0.4, 0.2, 0.1, 0.05, 0.03}) {
    s.spp = 512;
    s.adaptive_min_spp = 16;
    s.adaptive_threshold = threshold;
    s.seed = 8;
    const Timed t = timed_render(scene, traced, s);
    csv.row({std::string("adaptive"), threshold, t.result.mean_spp, t.seconds, t.cpu_seconds,
             rel_mse(t.result.image, reference), loom::bench::load_average()});
  }
  csv.save();
  loom::bench::plot(csv, {"cpu_seconds", "relmse", "method", "Cornell balls: adaptive vs uniform", true, true, ""});
}

// ---- BVH build ------------------------------------------------------------------------------

void bench_bvh() {
  Csv csv("pathtrace_bvh", {"triangles", "build_seconds", "build_cpu_seconds", "load1"});
  for (int rings : {71, 224, 708}) {
    loom::Scene scene;
    loom::SceneObject o;
    o.mesh = sphere_mesh(Eigen::Vector3d::Zero(), 1, rings, rings);
    scene.objects.push_back(o);
    std::size_t tris = 0;
    std::vector<double> cpu;
    const auto t = loom::bench::time_median(
        [&] {
          const double c0 = process_cpu_seconds();
          tris = EmbreeScene(scene).triangles();
          cpu.push_back(process_cpu_seconds() - c0);
        },
        3);
    std::sort(cpu.begin(), cpu.end());
    csv.row({(long long)tris, t.median, cpu[cpu.size() / 2], loom::bench::load_average()});
  }
  csv.save();
}

}  // namespace

int main(int argc, char** argv) {
  loom::bench::Cli cli("bench_pathtrace", "The path tracer's time-vs-error figures. Writes pathtrace_*.csv, plots and "
                                          "pathtrace/*.png.");
  std::vector<std::string> sections;
  cli.quick(quick, "a quarter of the reference samples and of the 512² repetitions")
      .modes(sections,
             {{"embree", "against Embree's tutorial path tracer on its Cornell box, 1 and 2 threads"},
              {"convergence", "relMSE against spp 4..1024 on the Cornell box"},
              {"strategies", "equal-time BSDF-only, NEE-only and MIS"},
              {"environment", "a one-pixel environment map: importance against uniform sampling"},
              {"adaptive", "adaptive thresholds against uniform spp"},
              {"bvh", "BVH build time of a 1M-triangle mesh"},
              {"cycles", "against Blender's Cycles (2 threads): relMSE per second, time to equal error"},
              {"rays", "Embree alone on PathTrace's rays and on its tutorial's: the ray-rate limit, 1 and 2 threads"},
              {"throughput", "paths per second, 1 thread (only when asked for)"},
              {"lanes", "an experiment: 16 paths in SIMD lanes against Embree's ray rate (only when asked for)"}},
             "sections to run (default: all but throughput and lanes)");
  cli.parse(argc, argv);
  const std::set<std::string> want(sections.begin(), sections.end());
  auto on = [&](const char* s) { return want.empty() || want.count(s); };
  std::cout << "load at start: " << loom::bench::load_average() << "\n";
  if (on("bvh")) bench_bvh();
  if (want.count("throughput")) bench_throughput();
  if (want.count("lanes")) bench::bench_lanes(quick);
  if (on("embree")) bench_embree();
  if (on("convergence")) bench_convergence();
  if (on("strategies")) {
    CornellBoxOptions o;
    strategies("cornell", cornell_box(o), 128);
    strategies("night", bench::night_scene(false), 128);
  }
  if (on("environment")) bench_environment();
  if (on("adaptive")) bench_adaptive();
  if (on("rays")) bench::bench_ray_rate(quick);
  if (on("cycles")) bench::bench_cycles(quick);
  return 0;
}
