#include "cycles_peer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include <tbb/global_control.h>
#include <nlohmann/json.hpp>

#include "bench_harness.hpp"
#include "cornell_box_scene.hpp"
#include "embree_scene.hpp"
#include "image_error.hpp"
#include "integrator.hpp"
#include "loom/error.hpp"
#include "scenes.hpp"

namespace loom::pathtrace::bench {

namespace {

namespace fs = std::filesystem;
using loom::bench::Csv;
using loom::bench::median;

constexpr int kThreads = 2;

// What cycles_render.py reads: world-space triangles, Lambert colour and
// emission per object, the sky colour, the camera. Only what both renderers
// share is written; anything else in the scene is an error.
nlohmann::json cycles_spec(const Scene& scene, const RenderSettings& s, const std::vector<int>& spp,
                           std::uint64_t seed) {
  if (!scene.lights.empty() || scene.environment.map || !scene.camera)
    throw Error("cycles peer: only emissive meshes, a uniform sky and a camera are exported");
  nlohmann::json objects = nlohmann::json::array();
  for (const SceneObject& o : scene.objects) {
    if (!o.mesh || o.material.model != Material::Model::diffuse || o.material.base_color_map || o.mesh->has_normals())
      throw Error("cycles peer: object '" + o.name + "' is not a flat-shaded diffuse mesh");
    nlohmann::json v = nlohmann::json::array(), f = nlohmann::json::array();
    for (Eigen::Index i = 0; i < o.mesh->V.rows(); ++i) {
      const Eigen::Vector4d p = o.transform * o.mesh->V.row(i).transpose().homogeneous();
      v.push_back({p.x(), p.y(), p.z()});
    }
    for (Eigen::Index i = 0; i < o.mesh->F.rows(); ++i)
      f.push_back({o.mesh->F(i, 0), o.mesh->F(i, 1), o.mesh->F(i, 2)});
    const auto& c = o.material.base_color;
    const auto& e = o.material.emission;
    objects.push_back({{"name", o.name.empty() ? "object" : o.name},
                       {"vertices", v},
                       {"faces", f},
                       {"color", {c.x(), c.y(), c.z()}},
                       {"emission", {e.x(), e.y(), e.z()}}});
  }
  const Camera& cam = *scene.camera;
  const Eigen::Vector3d sky = scene.environment.color * scene.environment.intensity;
  return {{"width", s.width},
          {"height", s.height},
          {"spp", spp},
          {"threads", kThreads},
          {"max_depth", s.max_depth},
          {"seed", seed},
          {"sky", {sky.x(), sky.y(), sky.z()}},
          {"camera",
           {{"eye", {cam.eye.x(), cam.eye.y(), cam.eye.z()}},
            {"target", {cam.target.x(), cam.target.y(), cam.target.z()}},
            {"up", {cam.up.x(), cam.up.y(), cam.up.z()}},
            {"fov_y", cam.fov_y}}},
          {"objects", objects}};
}

std::string sampling_pattern;  // Cycles' own default, as its last run reported it

struct Render {
  int spp;
  double seconds;
  cv::Mat image;
};

// One Blender process rendering every sample count of `spp` in turn (its
// first entry a warm-up: persistent data keeps the BVH for the others).
// Times are Cycles' render calls alone, as measured inside Blender.
std::vector<Render> run_cycles(const Scene& scene, const RenderSettings& s, const std::vector<int>& spp,
                               std::uint64_t seed) {
  const fs::path dir = fs::temp_directory_path() / "loom-bench-cycles";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "scene.json") << cycles_spec(scene, s, spp, seed).dump();
  const fs::path script = loom::bench::source_dir() / "bench" / "pathtrace" / "cycles_render.py";
  const std::string cmd = "blender -b --factory-startup -P '" + script.string() + "' -- '" +
                          (dir / "scene.json").string() + "' '" + dir.string() + "' > '" +
                          (dir / "blender.log").string() + "' 2>&1";
  if (std::system(cmd.c_str()) != 0) throw Error("blender failed: see " + (dir / "blender.log").string());
  std::vector<Render> out;
  std::ifstream times(dir / "times.jsonl");
  for (std::string line; std::getline(times, line);) {
    const auto j = nlohmann::json::parse(line);
    const int n = j.at("spp").get<int>();
    const fs::path pfm = dir / ("cycles_" + std::to_string(j.at("index").get<int>()) + ".pfm");
    cv::Mat image = read_pfm(pfm);
    if (image.empty()) throw Error("cycles peer: cannot read " + pfm.string());
    out.push_back({n, j.at("seconds").get<double>(), image});
    sampling_pattern = j.value("sampling_pattern", "");
  }
  if (out.size() != spp.size())
    throw Error("cycles peer: Blender stopped early: see " + (dir / "blender.log").string());
  return out;
}

Render run_loom(const Scene& scene, const EmbreeScene& traced, RenderSettings s, int spp, std::uint64_t seed) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, kThreads);
  s.spp = spp;
  s.seed = seed;
  const auto t = std::chrono::steady_clock::now();
  cv::Mat image = render(scene, *scene.camera, traced, s).image;
  return {spp, std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count(), image};
}

// log relMSE = a + b log t, least squares over a renderer's points.
struct PowerFit {
  double a = 0, b = 0;
  double seconds_for(double relmse) const { return std::exp((std::log(relmse) - a) / b); }
};
PowerFit fit(const std::vector<double>& seconds, const std::vector<double>& relmse) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = double(seconds.size());
  for (std::size_t i = 0; i < seconds.size(); ++i) {
    const double x = std::log(seconds[i]), y = std::log(relmse[i]);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  PowerFit f;
  f.b = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  f.a = (sy - f.b * sx) / n;
  return f;
}

// Per renderer and spp: times and errors of every round.
struct Measured {
  std::map<std::string, std::map<int, std::vector<double>>> seconds, relmse;
};

// The two references agree: means per channel and the relMSE between them.
void compare_references(const std::string& name, const cv::Mat& loom_ref, const cv::Mat& cycles_ref, Csv& csv) {
  const cv::Scalar ml = cv::mean(loom_ref), mc = cv::mean(cycles_ref);
  for (int ch = 0; ch < 3; ++ch)
    csv.row({name, std::string("reference mean, channel ") + "RGB"[ch], ml[ch], mc[ch], 100 * (ml[ch] / mc[ch] - 1),
             loom::bench::load_average()});
  csv.row({name, std::string("relMSE between the references"), rel_mse(loom_ref, cycles_ref),
           rel_mse(cycles_ref, loom_ref), std::string(""), loom::bench::load_average()});
}

// Rounds alternate which renderer goes first; every round has its own seeds.
// The time of N spp is the marginal cost (t(N) - t(1)) · N / (N - 1), with
// t(1) a 1-spp render of the same round, for both renderers: Cycles spends
// ~0.3 s per render call outside its sample loop (sync, film), which this
// takes out as it took out the model loading of Embree's tutorial.
Measured measure_rounds(const Scene& scene, const EmbreeScene& traced, const RenderSettings& s,
                        const std::vector<int>& spp, int rounds, const cv::Mat& loom_ref, const cv::Mat& cycles_ref,
                        Csv& raw, const std::string& name) {
  Measured m;
  auto record = [&](const std::string& who, int round, const Render& r, double one_spp, const cv::Mat& ref) {
    const double e = rel_mse(r.image, ref);
    const double marginal = (r.seconds - one_spp) * r.spp / (r.spp - 1);
    m.seconds[who][r.spp].push_back(marginal);
    m.relmse[who][r.spp].push_back(e);
    raw.row({name, who, (long long)round, (long long)r.spp, r.seconds, marginal, e, loom::bench::load_average()});
  };
  for (int round = 0; round < rounds; ++round) {
    const std::uint64_t seed = 100 + std::uint64_t(round);
    auto loom_runs = [&] {
      for (const auto& [who, kind] : {std::pair<std::string, SamplerKind>{"loom", SamplerKind::sobol},
                                      {"loom-independent", SamplerKind::independent}}) {
        RenderSettings t = s;
        t.sampler = kind;
        const double one_spp = run_loom(scene, traced, t, 1, seed).seconds;
        for (int n : spp) record(who, round, run_loom(scene, traced, t, n, seed), one_spp, loom_ref);
      }
    };
    auto cycles_runs = [&] {
      std::vector<int> list{1, 1};  // a warm-up (sync, BVH), then t(1)
      list.insert(list.end(), spp.begin(), spp.end());
      const auto renders = run_cycles(scene, s, list, seed);
      for (std::size_t i = 2; i < renders.size(); ++i)
        record("cycles", round, renders[i], renders[1].seconds, cycles_ref);
    };
    if (round % 2 == 0)
      loom_runs(), cycles_runs();
    else
      cycles_runs(), loom_runs();
  }
  return m;
}

// Per renderer and spp: the median time and mean relMSE over the rounds
// (pathtrace_cycles_NAME.csv and its plot); then the time to equal error: for
// each of Cycles' points, the time Loom's fitted curve needs for Cycles' error
// there, and the ratio (> 1: Loom is faster), in pathtrace_cycles_ratios.csv.
void summarize(const std::string& name, const Measured& m, Csv& ratios_csv) {
  Csv curve("pathtrace_cycles_" + name, {"renderer", "spp", "seconds", "relmse", "load1"});
  std::map<std::string, PowerFit> fits;
  std::map<std::string, std::vector<std::pair<double, double>>> points;  // (median s, mean relMSE)
  for (const auto& [who, by_spp] : m.seconds) {
    std::vector<double> t, e;
    for (const auto& [spp, secs] : by_spp) {
      const auto& errs = m.relmse.at(who).at(spp);
      double mean = 0;
      for (double x : errs) mean += x / double(errs.size());
      t.push_back(median(secs));
      e.push_back(mean);
      curve.row({who, (long long)spp, t.back(), e.back(), loom::bench::load_average()});
      points[who].push_back({t.back(), e.back()});
    }
    fits[who] = fit(t, e);
  }
  curve.save();
  loom::bench::plot(
      curve, {"seconds", "relmse", "renderer", name + ": relMSE against render time, 2 threads", true, true, ""});
  const auto& cycles_spp = m.seconds.at("cycles");
  for (const std::string who : {"loom", "loom-independent"}) {
    std::vector<double> ratios;
    auto spp = cycles_spp.begin();
    for (const auto& [tc, ec] : points["cycles"]) {
      ratios.push_back(tc / fits[who].seconds_for(ec));
      ratios_csv.row({name, who, (long long)(spp++)->first, tc, ec, ratios.back(), fits[who].b, fits["cycles"].b,
                      loom::bench::load_average()});
    }
    std::cout << "cycles, " << name << ": time to equal error, " << who << " vs Cycles = " << median(ratios)
              << "x (median over Cycles' " << ratios.size() << " spp; slopes of log relMSE / log time: " << who << " "
              << fits[who].b << ", cycles " << fits["cycles"].b << ")\n";
  }
}

void compare(const std::string& name, const Scene& scene, RenderSettings s, bool quick, Csv& raw, Csv& ratios,
             Csv& references) {
  const EmbreeScene traced(scene);
  const std::vector<int> spp = quick ? std::vector<int>{4, 16, 64} : std::vector<int>{4, 16, 64, 256};
  const int reference_spp = quick ? 1024 : 4096;
  s.sampler = SamplerKind::sobol;
  const cv::Mat loom_ref = run_loom(scene, traced, s, reference_spp, 4242).image;
  const cv::Mat cycles_ref = run_cycles(scene, s, {reference_spp}, 4242).front().image;
  save_png(loom_ref, "cycles-" + name + "-loom-reference.png");
  save_png(cycles_ref, "cycles-" + name + "-cycles-reference.png");
  compare_references(name, loom_ref, cycles_ref, references);
  const Measured m = measure_rounds(scene, traced, s, spp, quick ? 1 : 3, loom_ref, cycles_ref, raw, name);
  summarize(name, m, ratios);
}

}  // namespace

void bench_cycles(bool quick) {
  if (std::system("command -v blender > /dev/null 2>&1") != 0) {
    std::cout << "cycles: Blender is not installed (scripts/bench --cycles installs it): skipped\n";
    return;
  }
  Csv raw("pathtrace_cycles", {"scene", "renderer", "round", "spp", "seconds", "marginal_seconds", "relmse", "load1"});
  Csv ratios("pathtrace_cycles_ratios", {"scene", "renderer", "cycles_spp", "cycles_seconds", "cycles_relmse",
                                         "time_ratio_at_equal_error", "slope", "cycles_slope", "load1"});
  Csv references("pathtrace_cycles_references", {"scene", "what", "loom", "cycles", "difference_percent", "load1"});
  RenderSettings s;
  s.max_depth = 8;
  s.width = s.height = 128;
  compare("cornell", cornell_box(CornellBoxOptions{}), s, quick, raw, ratios, references);
  s.width = 160;
  s.height = 120;
  compare("emissive-mesh", emissive_mesh_scene(), s, quick, raw, ratios, references);
  raw.save();
  ratios.save();
  references.save();
  std::cout << "cycles: sampling pattern " << sampling_pattern << " (Blender's default)\n";
}

}  // namespace loom::pathtrace::bench
