// bench/shading: the Render node's rasterizer and the denoising method.
//  - speed: context creation, first frame (Mesa compiles shaders at the first
//    draw), steady state at 1920x1080, 4x MSAA, one light with a 2048² shadow
//    map and 5x5 PCF, against triangle count (10k..1M) and resolution;
//  - shadows: misclassified pixels against exact visibility (Embree ray casts)
//    over map resolution, constant bias (acne .. peter-panning), PCF size;
//  - normal mapping: image difference against true displaced geometry;
//  - denoising: RMS vertex distance and mean normal angle to the clean
//    surface, displacement map vs uniform and cotangent smoothing;
//  - limits: llvmpipe's fill rates and triangle rate beside the target
//    frame, and the fraction of the limit (llvmpipe_limits.hpp).
// Every row carries the 1-minute load average (the machine is shared).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <random>
#include <string>
#include <utility>

#include "bench_harness.hpp"
#include "exact_shadows.hpp"
#include "height_maps.hpp"
#include "llvmpipe_limits.hpp"
#include "loom/numerics/tangent_frames.hpp"
#include "mesh_denoising.hpp"
#include "rasterizer.hpp"
#include "shading_scenes.hpp"

namespace {

using namespace loom;
using namespace loom::shading;
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// A sphere of about `triangles` faces on a floor, one shadowed sun.
Scene speed_scene(int triangles) {
  const int rings = std::max(4, static_cast<int>(std::sqrt(triangles / 4.0)));
  Scene s;
  s.objects.push_back(scenes::object(scenes::plane(1, 4)));
  Mesh ball = scenes::sphere(rings, 2 * rings, 1);
  ball.V.col(1).array() += 1.2;
  SceneObject o = scenes::object(ball, {0.8, 0.4, 0.3});
  o.material.specular = 0.5;
  s.objects.push_back(o);
  Light sun;
  sun.kind = Light::Kind::directional;
  sun.direction = Eigen::Vector3d(-0.5, -1, -0.4).normalized();
  sun.intensity = 3;
  s.lights.push_back(sun);
  s.environment.color = {0.1, 0.1, 0.1};
  Camera c;
  c.eye = {0, 3, 6};
  c.target = {0, 0.8, 0};
  c.fov_y = 0.8;
  s.camera = c;
  return s;
}

// The target frame: 1080p, 4x MSAA, a 2048² map with 5x5 PCF.
RenderOptions target_options() {
  RenderOptions o;
  o.width = 1920;
  o.height = 1080;
  o.samples = 4;
  o.shadows = ShadowFilter::pcf;
  o.pcf_size = 5;
  o.shadow_resolution = 2048;
  return o;
}

double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t h = v.size() / 2;
  return v.size() % 2 ? v[h] : (v[h - 1] + v[h]) / 2;
}

long long triangles_of(const Scene& s) {
  long long n = 0;
  for (const auto& ob : s.objects) n += ob.mesh->faces();
  return n;
}

// only_target: context, first frame and the steady target row, nothing else.
void speed(bool quick, bool only_target = false) {
  bench::Csv csv("shading_speed", {"case", "triangles", "width", "height", "seconds", "cpu_seconds", "upload_s",
                                   "shadow_s", "draw_s", "readback_s", "shadow_cpu_s", "draw_cpu_s", "load1"});
  const auto t0 = Clock::now();
  const double c0 = loom::bench::process_cpu_seconds();
  Rasterizer r;
  const double create = since(t0);
  csv.row({"context+programs", 0LL, 0LL, 0LL, create, loom::bench::process_cpu_seconds() - c0, 0.0, 0.0, 0.0, 0.0, 0.0,
           0.0, loom::bench::load_average()});
  const RenderOptions o = target_options();
  const Scene target = speed_scene(100000);
  const long long tris = triangles_of(target);
  RenderTimings first;
  const auto t1 = Clock::now();
  const double c1 = loom::bench::process_cpu_seconds();
  r.render(target, o, &first);
  csv.row({"first frame", tris, 1920LL, 1080LL, since(t1), loom::bench::process_cpu_seconds() - c1, first.upload,
           first.shadows, first.draw, first.readback, first.shadows_cpu, first.draw_cpu, loom::bench::load_average()});
  // Each column the median of its runs (the passes' too: one run's would move with the load).
  auto steady = [&](const Scene& s, const RenderOptions& opt, const char* label, int runs) {
    std::vector<double> cpu, upload, shadow, draw, readback, shadow_cpu, draw_cpu;
    bool warm_up = true;  // time_median's first run, not timed
    const auto m = bench::time_median(
        [&] {
          RenderTimings t;
          const double c = loom::bench::process_cpu_seconds();
          r.render(s, opt, &t);
          if (std::exchange(warm_up, false)) return;
          cpu.push_back(loom::bench::process_cpu_seconds() - c);
          upload.push_back(t.upload);
          shadow.push_back(t.shadows);
          draw.push_back(t.draw);
          readback.push_back(t.readback);
          shadow_cpu.push_back(t.shadows_cpu);
          draw_cpu.push_back(t.draw_cpu);
        },
        runs);
    csv.row({label, triangles_of(s), static_cast<long long>(opt.width), static_cast<long long>(opt.height), m.median,
             median_of(cpu), median_of(upload), median_of(shadow), median_of(draw), median_of(readback),
             median_of(shadow_cpu), median_of(draw_cpu), loom::bench::load_average()});
  };
  steady(target, o, "steady 1080p", 5);
  RenderOptions no_shadow = o;
  no_shadow.shadows = ShadowFilter::off;
  steady(target, no_shadow, "no shadows 1080p", 3);
  RenderOptions no_msaa = o;
  no_msaa.samples = 1;
  steady(target, no_msaa, "no MSAA 1080p", 3);
  if (only_target) {
    csv.save();
    return;
  }
  for (int n : quick ? std::vector<int>{10000, 100000} : std::vector<int>{10000, 30000, 100000, 300000, 1000000})
    steady(speed_scene(n), o, "triangles", 3);
  for (auto [w, h] : std::vector<std::pair<int, int>>{{640, 360}, {1280, 720}, {1920, 1080}, {2560, 1440}}) {
    RenderOptions ro = o;
    ro.width = w;
    ro.height = h;
    steady(target, ro, "resolution", 3);
  }
  csv.save();
  bench::Csv tri("shading_triangles", {"time", "triangles", "seconds"});
  bench::Csv res("shading_resolution", {"time", "megapixels", "seconds"});
  for (const auto& row : csv.rows()) {
    const std::string label = std::get<std::string>(row[0]);
    for (int k : {4, 5}) {
      const std::string what = k == 4 ? "wall" : "CPU (all threads)";
      if (label == "triangles") tri.row({what, row[1], row[k]});
      if (label == "resolution")
        res.row({what, static_cast<double>(std::get<long long>(row[2]) * std::get<long long>(row[3])) / 1e6, row[k]});
    }
  }
  tri.save();
  res.save();
  bench::plot(tri, {"triangles", "seconds", "time", "Render time vs triangles (1080p, 4x MSAA, 2048 PCF 5x5)", true, true, ""});
  bench::plot(res, {"megapixels", "seconds", "time", "Render time vs resolution (100k triangles)", false, false, ""});
}

// The target frame beside llvmpipe's limits, alternating run by run.
void limits(bool quick) {
  Rasterizer r;
  const RenderOptions o = target_options();
  const Scene target = speed_scene(100000);
  RenderFrame f;
  f.run = [&](RenderTimings& t) { r.render(target, o, &t); };
  f.width = o.width;
  f.height = o.height;
  f.samples = o.samples;
  f.shadow_resolution = o.shadow_resolution;
  f.pcf_size = o.pcf_size;
  f.triangles = triangles_of(target);
  llvmpipe_limits(quick, f);
}

exact::ShadowComparison shadow_error(Rasterizer& r, Light::Kind kind, const RenderOptions& base) {
  const Scene scene = scenes::shadow_scene(kind);
  RenderOptions o = base;
  // 1440x960: a pixel is about 5.5 mm of floor, a 2048 directional texel 4 mm,
  // so map errors of a texel or more show outside the excluded edge band.
  o.width = 1440;
  o.height = 960;
  o.samples = 1;
  o.aux = true;
  const RenderImages im = r.render(scene, o);
  return exact::compare_shadows(exact::exact_visibility(scene, scene.lights[0], im.position, im.normal), im.shadow);
}

const char* kind_name(Light::Kind k) {
  return k == Light::Kind::point ? "point" : k == Light::Kind::spot ? "spot" : "directional";
}
const char* filter_name(ShadowFilter f) {
  return f == ShadowFilter::hard ? "hard" : f == ShadowFilter::pcf ? "pcf" : f == ShadowFilter::pcss ? "pcss" : "off";
}

void shadow_resolution(bool quick) {
  Rasterizer r;
  bench::Csv res("shadow_resolution", {"light_filter", "resolution", "misclassified_percent", "percent_of_shadow",
                                       "compared", "load1"});
  for (Light::Kind k : {Light::Kind::directional, Light::Kind::spot, Light::Kind::point})
    for (ShadowFilter f : {ShadowFilter::hard, ShadowFilter::pcf})
      for (int n : quick ? std::vector<int>{512, 2048} : std::vector<int>{256, 512, 1024, 2048, 4096}) {
        RenderOptions o;
        o.shadows = f;
        o.shadow_resolution = n;
        const auto c = shadow_error(r, k, o);
        res.row({std::string(kind_name(k)) + " " + filter_name(f), static_cast<long long>(n), 100 * c.rate(),
                 100 * c.rate_of_shadow(), static_cast<long long>(c.compared), loom::bench::load_average()});
      }
  res.save();
  bench::plot(res, {"resolution", "misclassified_percent", "light_filter",
                    "Misclassified pixels vs shadow-map resolution (default bias)", true, true, ""});
}

void shadow_bias(bool quick) {
  Rasterizer r;
  bench::Csv bias("shadow_bias", {"slope_bias", "bias_texels", "misclassified_percent", "percent_of_shadow", "load1"});
  for (double slope : {0.0, 1.0})
    for (double b : quick ? std::vector<double>{0.0625, 1, 128}
                          : std::vector<double>{0.0625, 0.125, 0.25, 0.5, 1, 2, 4, 8, 16, 32, 64, 128, 256}) {
      RenderOptions o;
      o.shadows = ShadowFilter::hard;
      o.shadow_bias = b;
      o.shadow_slope_bias = slope;
      const auto c = shadow_error(r, Light::Kind::directional, o);
      bias.row({slope == 0 ? std::string("slope 0") : std::string("slope 1"), b, 100 * c.rate(),
                100 * c.rate_of_shadow(), loom::bench::load_average()});
    }
  bias.save();
  bench::plot(bias, {"bias_texels", "misclassified_percent", "slope_bias",
                     "Bias sweep (directional, 2048, hard): acne left, peter-panning right", true, true, ""});
}

void shadow_pcf() {
  Rasterizer r;
  bench::Csv pcf("shadow_pcf", {"light", "pcf_size", "misclassified_percent", "percent_of_shadow", "load1"});
  for (Light::Kind k : {Light::Kind::directional, Light::Kind::spot, Light::Kind::point})
    for (int size : {1, 3, 5, 7, 9}) {
      RenderOptions o;
      o.shadows = ShadowFilter::pcf;
      o.pcf_size = size;
      const auto c = shadow_error(r, k, o);
      pcf.row({std::string(kind_name(k)), static_cast<long long>(size), 100 * c.rate(), 100 * c.rate_of_shadow(),
               loom::bench::load_average()});
    }
  pcf.save();
  bench::plot(pcf, {"pcf_size", "misclassified_percent", "light", "Misclassified pixels vs PCF kernel (2048)", false, false, ""});
}

void normal_mapping() {
  Rasterizer r;
  bench::Csv csv("normal_mapping", {"case", "sun_elevation_deg", "mean_abs_difference", "load1"});
  const cv::Mat height = bump_height(512, 512, 4, 4);
  const double scale = 0.08;
  auto normal_image = std::make_shared<Image>(height_to_normal_map(height, scale / 2, true), Encoding::linear);
  auto height_image = std::make_shared<Image>(height, Encoding::linear);
  Mesh displaced = scenes::plane(384, 1);
  for (Eigen::Index i = 0; i < displaced.V.rows(); ++i) {
    const double fx = displaced.UV(i, 0) * 512 - 0.5, fy = (1 - displaced.UV(i, 1)) * 512 - 0.5;
    const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
    const double ax = fx - x0, ay = fy - y0;
    auto at = [&](int x, int y) { return double(height.at<float>((y + 512) % 512, (x + 512) % 512)); };
    displaced.V(i, 1) += scale * ((1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x0 + 1, y0)) +
                                  ay * ((1 - ax) * at(x0, y0 + 1) + ax * at(x0 + 1, y0 + 1)));
  }
  displaced.N = loom::numerics::vertex_normals(displaced.V, displaced.F);
  for (double elevation : {10.0, 20.0, 45.0}) {
    auto view = [&](SceneObject o) {
      Scene s;
      Light sun;
      sun.kind = Light::Kind::directional;
      const double e = elevation * M_PI / 180;
      sun.direction = Eigen::Vector3d(-std::cos(e), -std::sin(e), 0);
      sun.intensity = 3;
      sun.casts_shadow = false;
      s.lights.push_back(sun);
      Camera c;
      c.projection = Camera::Projection::orthographic;
      c.eye = {0, 5, 0};
      c.up = {0, 0, -1};
      c.ortho_height = 1.6;
      s.camera = c;
      s.objects.push_back(o);
      RenderOptions ro;
      ro.width = ro.height = 256;
      ro.shadows = ShadowFilter::off;
      ro.tessellation = 32;
      return r.render(s, ro).color;
    };
    const cv::Mat truth = view(scenes::object(displaced));
    SceneObject flat = scenes::object(scenes::plane(16, 1));
    SceneObject mapped = flat;
    mapped.material.normal_map = normal_image;
    SceneObject tess = flat;
    tess.material.displacement_map = height_image;
    tess.material.displacement_scale = scale;
    auto diff = [&](const cv::Mat& a) {
      cv::Mat d;
      cv::absdiff(a, truth, d);
      const cv::Scalar m = cv::mean(d);
      return (m[0] + m[1] + m[2]) / 3;
    };
    csv.row({"flat", elevation, diff(view(flat)), loom::bench::load_average()});
    csv.row({"normal map", elevation, diff(view(mapped)), loom::bench::load_average()});
    csv.row({"tessellated displacement", elevation, diff(view(tess)), loom::bench::load_average()});
  }
  csv.save();
}

void denoising() {
  bench::Csv csv("denoising", {"method", "sigma", "steps", "rms_distance", "mean_normal_angle_deg", "seconds"});
  const int n = 120;
  Mesh clean = scenes::plane(n, 1);
  for (Eigen::Index i = 0; i < clean.V.rows(); ++i)
    clean.V(i, 1) = 0.15 * std::sin(M_PI * clean.V(i, 0)) * std::sin(M_PI * clean.V(i, 2));
  const Eigen::MatrixX3d N = loom::numerics::vertex_normals(clean.V, clean.F);
  for (double sigma : {0.002, 0.005, 0.01}) {
    std::mt19937_64 rng(7);
    std::normal_distribution<double> gauss(0, sigma);
    Eigen::MatrixX3d noisy = clean.V;
    for (Eigen::Index i = 0; i < noisy.rows(); ++i) noisy.row(i) += gauss(rng) * N.row(i);
    auto row = [&](const std::string& method, long long steps, const Eigen::MatrixX3d& V, double seconds) {
      const SurfaceError e = surface_error(V, clean.V, clean.F);
      csv.row({method, sigma, steps, e.rms_distance, e.mean_normal_angle * 180 / M_PI, seconds});
    };
    row("noisy", 0LL, noisy, 0.0);
    for (int steps : {1, 2, 3, 5}) {
      // The displacement method applied `steps` times (each: eqs. 44-45, bake, apply).
      auto t = Clock::now();
      Eigen::MatrixX3d V = noisy;
      for (int s = 0; s < steps; ++s) {
        const Eigen::MatrixX3d Nn = loom::numerics::vertex_normals(V, clean.F);
        const DisplacementMap map = bake_displacement(clean.UV, normal_displacements(V, clean.F, Nn), 512, 4);
        V = remove_displacement(V, Nn, sample_displacement(map, clean.UV));
      }
      row("displacement map", steps, V, since(t));
    }
    for (int steps : {1, 2, 5, 10, 20}) {
      auto t = Clock::now();
      const Eigen::MatrixX3d u = smooth(noisy, clean.F, SmoothingWeights::uniform, steps, 0.5);
      row("uniform Laplacian", steps, u, since(t));
      t = Clock::now();
      const Eigen::MatrixX3d c = smooth(noisy, clean.F, SmoothingWeights::cotangent, steps, 0.5);
      row("cotangent", steps, c, since(t));
    }
  }
  csv.save();
  bench::Csv plot_csv("denoising_sigma005", {"method", "steps", "mean_normal_angle_deg"});
  for (const auto& r : csv.rows())
    if (std::get<double>(r[1]) == 0.005 && std::get<std::string>(r[0]) != "noisy")
      plot_csv.row({r[0], r[2], r[4]});
  plot_csv.save();
  bench::plot(plot_csv, {"steps", "mean_normal_angle_deg", "method",
                         "Mean normal error after denoising (sigma 0.005)", false, false, ""});
}

}  // namespace

int main(int argc, char** argv) {
  loom::bench::Cli cli("bench_shading",
                       "The Render node's rasterizer, llvmpipe's limits beside it, and the denoising method. "
                       "Writes shading_*.csv, shadow_*.csv, normal_mapping.csv, denoising*.csv and plots.");
  bool quick = false;
  std::vector<std::string> parts;
  cli.quick(quick, "fewer triangle counts, shadow-map sizes and biases; limits: 3 runs, fewer quad counts")
      .modes(parts,
             {{"speed", "context, first frame and steady state against triangles and resolution"},
              {"target", "the issue's target case alone (only when asked for)"},
              {"shadows", "shadow-map errors against Embree ray casts: resolution, bias, PCF"},
              {"bias", "shadow errors over the constant bias"},
              {"pcf", "shadow errors over the PCF kernel size"},
              {"normals", "normal mapping against true displaced geometry"},
              {"denoise", "displacement-map denoising against smoothing"},
              {"limits", "llvmpipe's limits (LP_NUM_THREADS as set, else one thread per CPU): fill rate at "
                         "1080p with and without 4x MSAA (constant colour, no depth test), depth-only fill at "
                         "2048², the 5x5 PCF's gathers, 100k-triangle setup; alternated with the target frame; "
                         "fraction of the limit = limit time / Render's time (shading_limits.csv, "
                         "shading_fill_rate.csv + plot)"}},
             "parts to run (default: all but target)");
  cli.parse(argc, argv);
  auto want = [&](const char* p) { return parts.empty() || std::find(parts.begin(), parts.end(), p) != parts.end(); };
  if (want("speed")) speed(quick);
  if (!parts.empty() && want("target")) speed(quick, true);
  if (want("shadows")) shadow_resolution(quick);
  if (want("bias") || want("shadows")) shadow_bias(quick);
  if (want("pcf") || want("shadows")) shadow_pcf();
  if (want("normals")) normal_mapping();
  if (want("denoise")) denoising();
  if (want("limits")) limits(quick);
  return 0;
}
