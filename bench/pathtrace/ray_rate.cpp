#include "ray_rate.hpp"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_reduce.h>

#include "alternating.hpp"
#include "bench_harness.hpp"
#include "camera_rays.hpp"
#include "embree_ray_log.hpp"
#include "embree_scene.hpp"
#include "embree_tutorial.hpp"
#include "integrator.hpp"
#include "scenes.hpp"

namespace loom::pathtrace::bench {

namespace fs = std::filesystem;
using loom::bench::median;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

enum class RayKind : std::uint8_t { camera, bounce, shadow };

// Rays as Embree takes them, in the order the paths cast them, with what
// each found when recorded (a surface for closest-hit rays, a blocker for
// shadow rays), so that the timed loop can be checked to trace the same rays.
struct RecordedRays {
  std::vector<RTCRay> rays;
  std::vector<RayKind> kinds;
  std::uint64_t paths = 0, shadow = 0, found = 0;

  void add(const Vec3f& o, const Vec3f& d, float tfar, RayKind kind, bool found_something) {
    const unsigned mask = kind == RayKind::shadow ? EmbreeScene::kShadowMask : EmbreeScene::kCameraMask;
    add({o.x(), o.y(), o.z(), 0.f, d.x(), d.y(), d.z(), 0.f, tfar, mask, 0, 0}, kind, found_something);
  }
  void add(const RTCRay& ray, RayKind kind, bool found_something) {
    rays.push_back(ray);
    kinds.push_back(kind);
    shadow += kind == RayKind::shadow;
    found += found_something;
  }
};

// The rays PathTrace's path loop (integrator.cpp) casts on a scene of
// Lambertian surfaces lit by one point light, without roulette: a camera
// ray; at each hit a shadow ray to the light when the light is in front of
// the surface (as seen from the incoming ray), then a cosine-distributed
// bounce; a path ends on a miss, after max_depth hits, or when its
// throughput is zero (black after red, say).
RecordedRays record_paths(const Scene& scene, const EmbreeScene& traced, int size, int spp, int max_depth) {
  const CameraRays cam(*scene.camera, size, size);
  const Vec3f light = scene.lights.at(0).position.cast<float>();
  std::vector<Vec3f> albedo;
  for (const TracedObject& o : traced.objects())
    albedo.push_back(scene.objects[std::size_t(o.scene_index)].material.base_color.cast<float>());
  RecordedRays r;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      for (int s = 0; s < spp; ++s) {
        Rng rng(7, std::uint64_t(y) * size + x, std::uint64_t(s));
        const Vec2f j = rng.uniform2();
        Vec3f o, d;
        cam.ray(2 * (x + j.x()) / size - 1, 1 - 2 * (y + j.y()) / size, &o, &d);
        ++r.paths;
        Vec3f beta = Vec3f::Ones();
        for (int depth = 0; depth < max_depth; ++depth) {
          SurfaceHit hit;
          const bool found = traced.intersect(o, d, kInf, &hit, depth == 0);
          r.add(o, d, kInf, depth == 0 ? RayKind::camera : RayKind::bounce, found);
          if (!found) break;
          const Vec3f n = hit.ns.dot(d) > 0 ? Vec3f(-hit.ns) : hit.ns;
          if (n.dot(light - hit.p) > 0) {
            const EmbreeScene::Segment seg = traced.shadow_segment(hit, light);
            if (seg.tmax > 0)
              r.add(seg.origin, seg.direction, seg.tmax, RayKind::shadow,
                    traced.occluded(seg.origin, seg.direction, seg.tmax));
          }
          beta = beta.cwiseProduct(albedo[std::size_t(hit.object)]);
          if (!(beta.maxCoeff() > 0)) break;
          const Vec3f local = sample_cosine_hemisphere(rng.uniform2());
          if (!(local.z() > 0)) break;
          d = unit(Frame(n).to_world(local));
          o = traced.offset(hit, d);
        }
      }
  return r;
}

// Embree alone: every recorded ray once, rtcIntersect1 or rtcOccluded1 with
// the context flags PathTrace sets, in blocks of consecutive rays over TBB.
// Returns how many found a surface or a blocker.
std::uint64_t trace_recorded(const RecordedRays& r, RTCScene scene) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, r.rays.size(), 4096), std::uint64_t(0),
      [&](const tbb::blocked_range<std::size_t>& range, std::uint64_t found) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          RTCIntersectContext context;
          rtcInitIntersectContext(&context);
          if (r.kinds[i] == RayKind::shadow) {
            RTCRay ray = r.rays[i];
            rtcOccluded1(scene, &context, &ray);
            found += ray.tfar < 0;
            continue;
          }
          context.flags = r.kinds[i] == RayKind::camera ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT
                                                        : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
          RTCRayHit rh;
          rh.ray = r.rays[i];
          rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
          rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
          rtcIntersect1(scene, &context, &rh);
          found += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        }
        return found;
      },
      [](std::uint64_t a, std::uint64_t b) { return a + b; });
}

// Lane k of a packet from one recorded ray.
void to_lane(RTCRay16& p, int k, const RTCRay& r) {
  p.org_x[k] = r.org_x, p.org_y[k] = r.org_y, p.org_z[k] = r.org_z, p.tnear[k] = r.tnear;
  p.dir_x[k] = r.dir_x, p.dir_y[k] = r.dir_y, p.dir_z[k] = r.dir_z, p.time[k] = r.time;
  p.tfar[k] = r.tfar, p.mask[k] = r.mask, p.id[k] = r.id, p.flags[k] = r.flags;
}

// The same rays in Embree's 16-ray packets (rtcIntersect16 / rtcOccluded16):
// consecutive closest-hit rays in one packet, consecutive shadow rays in
// another, each traced when full (what a path tracer keeping 16 paths in
// flight could hand Embree). Returns how many found something.
std::uint64_t trace_recorded_packets(const RecordedRays& r, RTCScene scene) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, r.rays.size(), 4096), std::uint64_t(0),
      [&](const tbb::blocked_range<std::size_t>& range, std::uint64_t found) {
        RTCRayHit16 closest;
        RTCRay16 shadow;
        alignas(64) int valid[16];
        int nc = 0, ns = 0;
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        const auto trace_closest = [&] {
          for (int k = 0; k < 16; ++k) valid[k] = k < nc ? -1 : 0;
          rtcIntersect16(valid, scene, &context, &closest);
          for (int k = 0; k < nc; ++k) found += closest.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
          nc = 0;
        };
        const auto trace_shadow = [&] {
          for (int k = 0; k < 16; ++k) valid[k] = k < ns ? -1 : 0;
          rtcOccluded16(valid, scene, &context, &shadow);
          for (int k = 0; k < ns; ++k) found += shadow.tfar[k] < 0;
          ns = 0;
        };
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          if (r.kinds[i] == RayKind::shadow) {
            to_lane(shadow, ns++, r.rays[i]);
            if (ns == 16) trace_shadow();
            continue;
          }
          to_lane(closest.ray, nc, r.rays[i]);
          closest.hit.geomID[nc] = RTC_INVALID_GEOMETRY_ID;
          closest.hit.instID[0][nc++] = RTC_INVALID_GEOMETRY_ID;
          if (nc == 16) trace_closest();
        }
        if (nc > 0) trace_closest();
        if (ns > 0) trace_shadow();
        return found;
      },
      [](std::uint64_t a, std::uint64_t b) { return a + b; });
}

// The rays Embree's tutorial path tracer hands Embree on the same scene (its
// own camera, sampler and path loop: a shadow ray to the point light at each
// hit, then a bounce), recorded by embree_ray_log.cpp in one thread, so in
// the order its paths cast them. Empty, saying why, when the tutorial is not
// installed or its rays could not be recorded.
RecordedRays record_tutorial(int size, int spp, int max_depth) {
  RecordedRays r;
  if (!embree_tutorial_installed()) {
    std::cout << "rays: Embree's tutorial path tracer (embree-tools) is not installed: its columns are n/a\n";
    return r;
  }
  const fs::path log = tutorial_scratch("-rays.bin"), image = tutorial_scratch("-rays.pfm");
  std::error_code ignored;
  fs::remove(log, ignored);
  const bool ran =
      run_embree_tutorial(size, spp, max_depth, 1, image, nullptr,
                          "LD_PRELOAD='" EMBREE_RAY_LOG_MODULE "' LOOM_EMBREE_RAY_LOG='" + log.string() + "'") >= 0;
  std::ifstream in(log, std::ios::binary);
  LoggedRay l;
  while (ran && in.read(reinterpret_cast<char*>(&l), sizeof l)) {
    const RayKind kind = l.shadow                                          ? RayKind::shadow
                         : (l.flags & RTC_INTERSECT_CONTEXT_FLAG_COHERENT) ? RayKind::camera
                                                                           : RayKind::bounce;
    r.add(l.ray, kind, l.found);
  }
  r.paths = std::uint64_t(size) * std::uint64_t(size) * std::uint64_t(spp);
  if (r.rays.empty())
    std::cout << "rays: no rays recorded from Embree's tutorial (" EMBREE_RAY_LOG_MODULE
                 " loaded with LD_PRELOAD): its columns are n/a\n";
  fs::remove(log, ignored);
  fs::remove(image, ignored);
  return r;
}

// The tutorial's rendering time per path: its marginal cost, (t(spp) - t(1))
// scaled to spp, so that loading the model and building its BVH cancel (as
// the `embree` mode times it). Appends wall and CPU seconds per path.
void time_tutorial(int size, int spp, int max_depth, int threads, std::vector<double>* wall, std::vector<double>* cpu) {
  const fs::path image = tutorial_scratch("-rays.pfm");
  const TutorialSeconds t = time_embree_tutorial(size, spp, max_depth, threads, image);
  const double paths = double(size) * size * spp;
  wall->push_back(t.wall / paths);
  cpu->push_back(t.cpu / paths);
  std::error_code ignored;
  fs::remove(image, ignored);
}

// One scene's rows: PathTrace's render, Embree alone on its recorded rays (one
// ray per call and in packets) and, when `tutorial` holds rays, Embree's
// tutorial path tracer and Embree alone on its rays, alternating, with 1 and
// 2 threads.
void rate_on(const std::string& name, const Scene& scene, const RecordedRays& tutorial, bool quick,
             loom::bench::Csv& csv) {
  const EmbreeScene traced(scene);
  long long triangles = 0;
  for (const SceneObject& o : scene.objects) triangles += o.mesh->F.rows();
  RenderSettings s;  // as the `embree` mode renders it
  s.width = s.height = quick ? 128 : 256;
  s.spp = 16;
  s.max_depth = 8;
  s.russian_roulette = false;
  const RecordedRays recorded = record_paths(scene, traced, 128, quick ? 4 : 8, s.max_depth);
  const int passes = quick ? 2 : 4;  // over the recorded rays per timed run
  const double recorded_per_path = double(recorded.rays.size()) / double(recorded.paths);
  const double recorded_shadow = double(recorded.shadow) / double(recorded.rays.size());
  const bool have_tutorial = !tutorial.rays.empty();
  const double tutorial_per_path = have_tutorial ? double(tutorial.rays.size()) / double(tutorial.paths) : 0;
  for (int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    RenderResult ours;
    bool same = true, same_packets = true, same_tutorial = true;
    std::vector<double> tutorial_wall, tutorial_cpu;  // seconds per path (a child process: timed by itself)
    std::vector<std::function<void()>> contenders = {
        [&] { ours = render(scene, *scene.camera, traced, s); },
        [&] {
          for (int p = 0; p < passes; ++p)
            same = trace_recorded(recorded, traced.rtc_scene()) == recorded.found && same;
        },
        [&] {
          for (int p = 0; p < passes; ++p)
            same_packets = trace_recorded_packets(recorded, traced.rtc_scene()) == recorded.found && same_packets;
        }};
    if (have_tutorial) {
      contenders.push_back([&] {
        for (int p = 0; p < passes; ++p)
          same_tutorial = trace_recorded(tutorial, traced.rtc_scene()) == tutorial.found && same_tutorial;
      });
      contenders.push_back([&] { time_tutorial(s.width, s.spp, s.max_depth, threads, &tutorial_wall, &tutorial_cpu); });
    }
    const auto t = loom::bench::time_alternating(quick ? 1 : 5, contenders);
    const double loom_rays = double(ours.rays), embree_rays = double(recorded.rays.size()) * passes;
    const double lw = loom_rays / t[0].wall, ew = embree_rays / t[1].wall;
    const double lc = loom_rays / t[0].cpu, ec = embree_rays / t[1].cpu, pc = embree_rays / t[2].cpu;
    // Embree's tutorial on its own rays (its rays per path over its time per path).
    const double tutorial_rays = double(tutorial.rays.size()) * passes;
    const double tw = have_tutorial ? tutorial_per_path / median(tutorial_wall) : 0;
    const double tc = have_tutorial ? tutorial_per_path / median(tutorial_cpu) : 0;
    const double etw = have_tutorial ? tutorial_rays / t[3].wall : 1;
    const double etc = have_tutorial ? tutorial_rays / t[3].cpu : 1;
    const auto tutorial_cell = [&](double v) {
      return have_tutorial ? loom::bench::Cell(v) : loom::bench::Cell(std::string("n/a"));
    };
    const std::string tutorial_match = !have_tutorial ? "n/a" : same_tutorial ? "yes" : "no";
    const double tutorial_shadow = have_tutorial ? double(tutorial.shadow) / double(tutorial.rays.size()) : 0;
    csv.row({name,
             triangles,
             (long long)threads,
             lw,
             ew,
             lw / ew,
             lc,
             ec,
             lc / ec,
             loom_rays / double(ours.paths),
             double(ours.shadow_rays) / loom_rays,
             recorded_per_path,
             recorded_shadow,
             std::string(same ? "yes" : "no"),
             pc,
             lc / pc,
             std::string(same_packets ? "yes" : "no"),
             tutorial_cell(tw),
             tutorial_cell(etw),
             tutorial_cell(tw / etw),
             tutorial_cell(tc),
             tutorial_cell(etc),
             tutorial_cell(tc / etc),
             tutorial_cell(tutorial_per_path),
             tutorial_cell(tutorial_shadow),
             tutorial_match,
             loom::bench::load_average()});
    std::cout << "rays, " << name << ", " << threads << " thread(s): PathTrace " << lw / 1e6
              << " M rays/s, Embree alone " << ew / 1e6 << " M rays/s: " << 100 * lw / ew
              << " % of the limit (per CPU second " << 100 * lc / ec << " %; of Embree's rate in 16-ray packets, "
              << pc / 1e6 << " M rays per CPU s: " << 100 * lc / pc << " %)\n";
    if (have_tutorial)
      std::cout << "rays, " << name << ", " << threads << " thread(s): Embree's tutorial path tracer " << tw / 1e6
                << " M rays/s, Embree alone on its rays " << etw / 1e6 << " M rays/s: " << 100 * tw / etw
                << " % of the limit (per CPU second " << 100 * tc / etc << " %)\n";
  }
}

}  // namespace

void bench_ray_rate(bool quick) {
  loom::bench::Csv csv("pathtrace_rays", {"scene",
                                          "triangles",
                                          "threads",
                                          "loom_rays_per_s",
                                          "embree_rays_per_s",
                                          "fraction",
                                          "loom_rays_per_cpu_s",
                                          "embree_rays_per_cpu_s",
                                          "fraction_cpu",
                                          "loom_rays_per_path",
                                          "loom_shadow_share",
                                          "recorded_rays_per_path",
                                          "recorded_shadow_share",
                                          "outcomes_match",
                                          "embree_packets_rays_per_cpu_s",
                                          "fraction_of_packets_cpu",
                                          "packet_outcomes_match",
                                          "tutorial_rays_per_s",
                                          "embree_on_tutorial_rays_per_s",
                                          "tutorial_fraction",
                                          "tutorial_rays_per_cpu_s",
                                          "embree_on_tutorial_rays_per_cpu_s",
                                          "tutorial_fraction_cpu",
                                          "tutorial_rays_per_path",
                                          "tutorial_shadow_share",
                                          "tutorial_outcomes_match",
                                          "load1"});
  const RecordedRays tutorial = record_tutorial(128, quick ? 4 : 8, 8);
  rate_on("cornell", embree_cornell_box(EMBREE_MODELS), tutorial, quick, csv);
  // The same box with a ball of 2M triangles (500k with --quick): a scene
  // whose rays cost Embree twice the traversal.
  rate_on("cornell+ball", embree_cornell_box_with_ball(EMBREE_MODELS, quick ? 354 : 707), {}, quick, csv);
  csv.save();
}

}  // namespace loom::pathtrace::bench
