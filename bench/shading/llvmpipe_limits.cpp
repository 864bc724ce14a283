#include "llvmpipe_limits.hpp"

#include <algorithm>
#include <cstdlib>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "alternating.hpp"
#include "bench_harness.hpp"
#include "limit_rig.hpp"

namespace loom::shading {

namespace {

using loom::bench::Csv;
using loom::bench::median;

// LP_NUM_THREADS as llvmpipe reads it when the first context is made (unset:
// one rasterizer thread per CPU).
std::string lp_threads() {
  const char* v = std::getenv("LP_NUM_THREADS");
  return v ? std::string(v) : std::to_string(std::thread::hardware_concurrency()) + " (default: CPUs)";
}

// Fill rate against quads per frame: the rate must level off (a frame's
// clear and flush amortized) and time grow with the quads (nothing dropped).
void fill_rate_sweep(LimitRig& rig, bool quick) {
  using T = LimitRig::Target;
  using S = LimitRig::Shading;
  Csv csv("shading_fill_rate", {"target", "quads", "seconds", "mpixels_per_s", "lp_threads", "load1"});
  const std::vector<std::tuple<const char*, T, S>> cases = {{"1080p 1x constant", T::image, S::constant},
                                                            {"1080p 4x MSAA constant", T::image_msaa, S::constant},
                                                            {"2048^2 depth only", T::shadow_map, S::depth_only},
                                                            {"1080p 4x MSAA PCF gathers", T::image_msaa, S::pcf}};
  for (const auto& [name, target, shading] : cases)
    for (int q : quick ? std::vector<int>{1, 4, 16} : std::vector<int>{1, 2, 4, 8, 16}) {
      const auto t = loom::bench::time_median(
          [&, target = target, shading = shading] { rig.quads(target, shading, q); }, quick ? 3 : 5);
      csv.row({std::string(name), static_cast<long long>(q), t.median, q * rig.pixels(target) / t.median * 1e-6,
               lp_threads(), loom::bench::load_average()});
    }
  csv.save();
  loom::bench::plot(
      csv, {"quads", "mpixels_per_s", "target",
            "llvmpipe fill rate vs full-screen quads per frame (" + lp_threads() + " threads)", true, true, ""});
}

}  // namespace

void llvmpipe_limits(bool quick, const RenderFrame& render) {
  using T = LimitRig::Target;
  using S = LimitRig::Shading;
  LimitRig rig(render);
  fill_rate_sweep(rig, quick);

  // Render's frame and the limit runs alternate round by round; the quad runs
  // draw `q` quads per frame so that clear and flush weigh little in the rate.
  const int q = 16, runs = quick ? 3 : 7;
  std::vector<double> shadow_s, draw_s, readback_s, upload_s, shadow_cpu, draw_cpu, readback_cpu;
  const auto t = loom::bench::time_alternating(
      runs, {[&] {
               RenderTimings r;
               render.run(r);
               shadow_s.push_back(r.shadows);
               draw_s.push_back(r.draw);
               readback_s.push_back(r.readback);
               upload_s.push_back(r.upload);
               shadow_cpu.push_back(r.shadows_cpu);
               draw_cpu.push_back(r.draw_cpu);
               readback_cpu.push_back(r.readback_cpu);
             },
             [&] { rig.quads(T::image, S::constant, q); }, [&] { rig.quads(T::image_msaa, S::constant, q); },
             [&] { rig.quads(T::shadow_map, S::depth_only, q); }, [&] { rig.quads(T::image_msaa, S::pcf, q); },
             [&] { rig.grid(T::shadow_map, S::depth_only); }, [&] { rig.grid(T::image_msaa, S::constant); },
             [&] { rig.quads(T::shadow_map, S::depth_only, 0); }, [&] { rig.quads(T::image_msaa, S::constant, 0); },
             [&] { rig.grid(T::image_msaa, S::constant, true); }});
  const double load = loom::bench::load_average();
  const double px = rig.pixels(T::image), texels = rig.pixels(T::shadow_map);
  const double fill1 = q * px / t[1].wall, fill4 = q * px / t[2].wall, depth = q * texels / t[3].wall,
               pcf4 = q * px / t[4].wall;
  const double frame = t[0].wall, shadow = median(shadow_s), draw = median(draw_s);
  const double tris = static_cast<double>(rig.grid_triangles());

  Csv csv("shading_limits",
          {"measure", "seconds", "cpu_seconds", "rate", "rate_unit", "fraction_of_limit", "lp_threads", "load1"});
  auto row = [&](const std::string& what, double s, double cpu, double rate, const std::string& unit, double fraction) {
    csv.row({what, s, cpu, rate, unit, fraction, lp_threads(), load});
  };
  const std::string Q = " (" + std::to_string(q) + " full-screen quads)";
  row("Render frame (wall; passes below)", frame, t[0].cpu, 1 / frame, "frames/s", 0);
  row("Render upload", median(upload_s), 0, 0, "", 0);
  row("Render shadow pass", shadow, median(shadow_cpu), 0, "", 0);
  row("Render main pass (clear, draw, shade)", draw, median(draw_cpu), 0, "", 0);
  row("Render resolve + readback", median(readback_s), median(readback_cpu), 0, "", 0);
  row("fill 1080p 1x, constant colour, no depth test" + Q, t[1].wall, t[1].cpu, fill1 * 1e-6, "Mpixel/s", 0);
  row("fill 1080p 4x MSAA, constant colour, no depth test" + Q, t[2].wall, t[2].cpu, fill4 * 1e-6, "Mpixel/s", 0);
  row("depth-only fill 2048^2, GL_LESS" + Q, t[3].wall, t[3].cpu, depth * 1e-6, "Mtexel/s", 0);
  row("fill 1080p 4x MSAA + 5x5 PCF gathers" + Q, t[4].wall, t[4].cpu, pcf4 * 1e-6, "Mpixel/s", 0);
  const std::string G = std::to_string(rig.grid_triangles()) + " 2-pixel triangles, clear included";
  row("setup: " + G + ", depth only 2048^2", t[5].wall, t[5].cpu, tris / t[5].wall * 1e-6, "Mtriangle/s", 0);
  row("setup: " + G + ", 1080p 4x MSAA", t[6].wall, t[6].cpu, tris / t[6].wall * 1e-6, "Mtriangle/s", 0);
  row("setup: " + G + ", half of them culled, 1080p 4x MSAA", t[9].wall, t[9].cpu, tris / t[9].wall * 1e-6,
      "Mtriangle/s", 0);
  row("clear 2048^2 depth (frame of no draws)", t[7].wall, t[7].cpu, texels / t[7].wall * 1e-6, "Mtexel/s", 0);
  row("clear 1080p 4x MSAA colour + depth (frame of no draws)", t[8].wall, t[8].cpu, px / t[8].wall * 1e-6, "Mpixel/s",
      0);
  // The frame at llvmpipe's rates: every pixel (4x MSAA) and map texel once
  // at the raw fill rates; then with the PCF gathers on every pixel; then
  // with each pass's clear and triangles added (the grid runs). The resolve
  // and readback are not fill: they stay outside every limit.
  const double raw = px / fill4 + texels / depth;
  const double with_pcf = px / pcf4 + texels / depth;
  const double shadow_limit = t[5].wall + texels / depth, main_limit = t[6].wall + px / pcf4;
  // Render culls the hidden half of a closed mesh (the sphere): its main
  // pass rasterizes half the triangles it sends.
  const double main_limit_culled = t[9].wall + px / pcf4;
  row("limit: raw fill (1080p 4x + 2048^2 depth) / Render frame", raw, 0, 0, "", raw / frame);
  row("limit: fill + PCF gathers / Render frame", with_pcf, 0, 0, "", with_pcf / frame);
  row("limit: + clears and triangles / Render frame", shadow_limit + main_limit, 0, 0, "",
      (shadow_limit + main_limit) / frame);
  row("limit: + clears and triangles / Render shadow + main pass", shadow_limit + main_limit, 0, 0, "",
      (shadow_limit + main_limit) / (shadow + draw));
  row("limit: shadow pass (triangles + depth fill) / Render shadow pass", shadow_limit, 0, 0, "",
      shadow_limit / shadow);
  row("limit: main pass (triangles + fill + PCF) / Render main pass", main_limit, 0, 0, "", main_limit / draw);
  row("limit: main pass, half the triangles culled / Render main pass", main_limit_culled, 0, 0, "",
      main_limit_culled / draw);
  // The same fractions in CPU seconds (all threads): a loaded machine moves
  // them much less than wall time, which also counts the waits for a core.
  const double shadow_limit_cpu = t[5].cpu + t[3].cpu / q, main_limit_cpu = t[6].cpu + t[4].cpu / q,
               main_limit_culled_cpu = t[9].cpu + t[4].cpu / q;
  row("limit in CPU-s: shadow pass / Render shadow pass", shadow_limit_cpu, shadow_limit_cpu, 0, "",
      shadow_limit_cpu / median(shadow_cpu));
  row("limit in CPU-s: main pass / Render main pass", main_limit_cpu, main_limit_cpu, 0, "",
      main_limit_cpu / median(draw_cpu));
  row("limit in CPU-s: main pass, half the triangles culled / Render main pass", main_limit_culled_cpu,
      main_limit_culled_cpu, 0, "", main_limit_culled_cpu / median(draw_cpu));
  csv.save();
}

}  // namespace loom::shading
