#include "lanes.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <optional>
#include <vector>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "alternating.hpp"
#include "bench_harness.hpp"
#include "camera_rays.hpp"
#include "cornell_box_scene.hpp"
#include "embree_scene.hpp"
#include "image_error.hpp"
#include "integrator.hpp"
#include "lane_paths.hpp"
#include "light_sampler.hpp"
#include "path_loop.hpp"
#include "scenes.hpp"

namespace loom::pathtrace::bench {

namespace {

// 16 paths in flight, each lane one path, structure of arrays. The shading
// loop over the lanes has no branches, so GCC turns it into SSE2 over 4 × 4
// lanes; the gathers (albedo, PathTrace's pixel sampler per lane) are scalar.
struct Lanes {
  alignas(64) float ox[kLanes], oy[kLanes], oz[kLanes], dx[kLanes], dy[kLanes], dz[kLanes];
  alignas(64) float br[kLanes], bg[kLanes], bb[kLanes];        // throughput
  alignas(64) int depth[kLanes], pixel[kLanes], live[kLanes];  // live: -1 or 0, as Embree's valid masks
};

// What one lane's bounce leaves for the film and the shadow ray.
struct Shading {
  alignas(64) float sx[kLanes], sy[kLanes], sz[kLanes], sdx[kLanes], sdy[kLanes], sdz[kLanes], stmax[kLanes];
  alignas(64) float cr[kLanes], cg[kLanes], cb[kLanes];  // the light's contribution if unblocked
  alignas(64) int shadow[kLanes];                        // -1: a shadow ray to trace
};

struct Setup {
  const EmbreeScene& traced;
  CameraRays camera;
  int size, spp, max_depth;
  SamplerKind sampler;  // PathTrace's own samples: the same numbers for the same pixel, sample and seed
  std::uint64_t seed;
  float light[3], intensity;
  // Per traced object, its material's base color; an object's index is its
  // Embree geometry id (this scene has no instances).
  std::vector<Vec3f> base;
  bool packets = true;  // 16-ray packets, or each live lane's ray in a call of its own
  // Set: the general variant, which takes each hit from PathTrace's own hit
  // assembly (EmbreeScene::surface_hit) and its light sample from
  // PathTrace's LightSampler, one lane at a time, and shades the lanes with
  // the shading normal, the base color times the hit's color and MIS weights.
  const LightSampler* lights = nullptr;
};

// A packet as the lane loop handed it to Embree, and how many of its rays
// found a surface or a blocker.
struct Packet {
  alignas(64) int valid[kLanes];
  RTCRay16 rays;
  bool shadow;
  int found;
};

// A packet as the loop hands it to Embree, kept for the replay; returns where
// its count of hits or blockers goes.
int* record_packet(std::vector<Packet>& record, const int* valid, const RTCRay16& rays, bool shadow) {
  record.emplace_back();
  std::copy(valid, valid + kLanes, record.back().valid);
  record.back().rays = rays;
  record.back().shadow = shadow;
  return &record.back().found;
}

// A cosine-weighted direction about the unit normal n for the pair (u1, u2)
// (Malley), in the frame of Duff et al. 2017; the angle's cos and sin by
// sampling.hpp's quadrant rule, its Taylor series two terms shorter
// (truncation below 4e-7) and the quadrant selected without a switch, so
// that a loop over the lanes that calls it stays free of branches.
inline void cosine_bounce(float nx, float ny, float nz, float u1, float u2, float& dx, float& dy, float& dz) {
  const float r = std::sqrt(u1), zl = std::sqrt(1 - u1);
  const int q = int(4 * u2 + 0.5f);
  const float a = (4 * u2 - float(q)) * 1.57079633f, a2 = a * a;
  const float sa = a * (1 + a2 * (-1.f / 6 + a2 * (1.f / 120 + a2 * (-1.f / 5040))));
  const float ca = 1 + a2 * (-0.5f + a2 * (1.f / 24 + a2 * (-1.f / 720 + a2 * (1.f / 40320))));
  const int qq = q & 3;
  const float c = qq == 0 ? ca : qq == 1 ? -sa : qq == 2 ? -ca : sa;
  const float sn = qq == 0 ? sa : qq == 1 ? ca : qq == 2 ? -sa : -ca;
  const float xl = r * c, yl = r * sn;
  const float sign = nz >= 0 ? 1.f : -1.f, fa = -1 / (sign + nz), fb = nx * ny * fa;
  const float tx = 1 + sign * nx * nx * fa, ty = sign * fb, tz = -sign * nx;
  const float bx = fb, by = sign + ny * ny * fa, bz = -ny;
  dx = xl * tx + yl * bx + zl * nx;
  dy = xl * ty + yl * by + zl * ny;
  dz = xl * tz + yl * bz + zl * nz;
}

// The bounce at each lane's hit for the scene's lone point light, with the
// hit's geometric normal and its object's albedo: scalar gathers, then one
// loop over the lanes.
void shade_point_light(const Setup& s, const RTCRayHit16& rh, std::optional<PixelSampler>* samplers, Lanes& L,
                       Shading& S) {
  // Each lane's bounce direction pair; lanes without a hit compute on zeros, masked out.
  alignas(64) float u1[kLanes]{}, u2[kLanes]{};
  // Gathers, scalar: each hit's albedo and its bounce pair from the lane's sampler.
  alignas(64) float ar[kLanes], ag[kLanes], ab[kLanes];
  alignas(64) int hit[kLanes];
  for (int k = 0; k < kLanes; ++k) {
    const unsigned g = rh.hit.geomID[k];
    hit[k] = L.live[k] & (g != RTC_INVALID_GEOMETRY_ID ? -1 : 0);
    const Vec3f& albedo = s.base[hit[k] ? g : 0];
    ar[k] = albedo.x(), ag[k] = albedo.y(), ab[k] = albedo.z();
    // The bounce's pair, drawn as PathTrace draws it (a lone point light: no light pair).
    if (!hit[k]) continue;
    samplers[k]->start_bounce(L.depth[k], false);
    const Vec2f u = samplers[k]->uniform2(Decision::direction);
    u1[k] = u.x(), u2[k] = u.y();
  }
  // The hit, next-event estimation and the bounce, lane-parallel (no
  // branches: every lane computes, masks decide what counts).
  const float light_x = s.light[0], light_y = s.light[1], light_z = s.light[2], intensity = s.intensity;
  const int max_depth = s.max_depth;
  for (int k = 0; k < kLanes; ++k) {
    const float t = rh.ray.tfar[k];
    const float px = L.ox[k] + t * L.dx[k], py = L.oy[k] + t * L.dy[k], pz = L.oz[k] + t * L.dz[k];
    float nx = rh.hit.Ng_x[k], ny = rh.hit.Ng_y[k], nz = rh.hit.Ng_z[k];
    const float inv_n = 1 / std::sqrt(nx * nx + ny * ny + nz * nz + 1e-30f);
    const float flip = ((nx * L.dx[k] + ny * L.dy[k] + nz * L.dz[k]) > 0 ? -1.f : 1.f) * inv_n;
    nx *= flip, ny *= flip, nz *= flip;
    const float eps = 1e-4f * (1 + std::max(std::fabs(px), std::max(std::fabs(py), std::fabs(pz))));
    const float qx = px + eps * nx, qy = py + eps * ny, qz = pz + eps * nz;  // off the surface, outward
    // Shadow ray to the point light: (I / d²) · cos · albedo / π.
    const float lx = light_x - qx, ly = light_y - qy, lz = light_z - qz;
    const float l2 = lx * lx + ly * ly + lz * lz, inv_l = 1 / std::sqrt(l2);
    const float cos_l = (lx * nx + ly * ny + lz * nz) * inv_l;
    const float w = (cos_l > 0 ? 1.f : 0.f) * (intensity * cos_l * kInvPi / l2);
    S.sx[k] = qx, S.sy[k] = qy, S.sz[k] = qz;
    S.sdx[k] = lx * inv_l, S.sdy[k] = ly * inv_l, S.sdz[k] = lz * inv_l, S.stmax[k] = l2 * inv_l - eps;
    S.cr[k] = w * L.br[k] * ar[k], S.cg[k] = w * L.bg[k] * ag[k], S.cb[k] = w * L.bb[k] * ab[k];
    S.shadow[k] = hit[k] & (cos_l > 0 ? -1 : 0);
    cosine_bounce(nx, ny, nz, u1[k], u2[k], L.dx[k], L.dy[k], L.dz[k]);
    L.ox[k] = qx, L.oy[k] = qy, L.oz[k] = qz;
    L.br[k] *= ar[k], L.bg[k] *= ag[k], L.bb[k] *= ab[k];
    L.depth[k] += 1;
    const int on = (L.depth[k] < max_depth) & ((L.br[k] > 0) | (L.bg[k] > 0) | (L.bb[k] > 0));
    L.live[k] = hit[k] & -on;
  }
}

// What PathTrace's own code gives a lane at its hit (EmbreeScene::surface_hit,
// LightSampler::sample), gathered one lane at a time for the lane loop.
struct Gathered {
  alignas(64) float px[kLanes], py[kLanes], pz[kLanes], eps[kLanes];
  alignas(64) float gx[kLanes], gy[kLanes], gz[kLanes], nx[kLanes], ny[kLanes], nz[kLanes];
  alignas(64) float ar[kLanes], ag[kLanes], ab[kLanes];  // base color times the hit's color
  alignas(64) float wx[kLanes], wy[kLanes], wz[kLanes], lr[kLanes], lg[kLanes], lb[kLanes], lpdf[kLanes];
  alignas(64) float qx[kLanes], qy[kLanes], qz[kLanes], q_eps[kLanes];  // the light's point and its offset
  alignas(64) float u1[kLanes], u2[kLanes];                             // the bounce direction pair
  alignas(64) float delta[kLanes];                                      // 1 for a delta light, else 0
  alignas(64) int hit[kLanes], light[kLanes];                           // -1 or 0
};

// The bounce at each lane's hit as PathTrace's path loop computes it for a
// Lambertian surface (integrator.cpp: sample_direct, LambertBsdf, scatter):
// the hit and the light sample from PathTrace's code one lane at a time,
// then NEE with the power heuristic, the shadow segment, the cosine bounce
// and the offsets in one loop over the lanes. Not here: emission at hits,
// the environment, normal maps, textures, roulette, lights without shadows,
// a light's point within the offsets of the hit (PathTrace adds its light
// untested; this loop drops it).
void shade_general(const Setup& s, const RTCRayHit16& rh, std::optional<PixelSampler>* samplers, Lanes& L, Shading& S) {
  Gathered G{};  // lanes without a hit or a light compute on zeros, masked out
  const bool light_point = s.lights->reads_point();
  for (int k = 0; k < kLanes; ++k) {
    G.hit[k] = L.live[k] & (rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID ? -1 : 0);
    G.light[k] = 0, G.delta[k] = 0.f;
    if (!G.hit[k]) continue;
    SurfaceHit h;
    s.traced.surface_hit({L.ox[k], L.oy[k], L.oz[k]}, {L.dx[k], L.dy[k], L.dz[k]}, rh.ray.tfar[k], rh.hit.geomID[k],
                         rh.hit.primID[k], rh.hit.u[k], rh.hit.v[k], &h);
    const Vec3f base = s.base[std::size_t(h.object)].cwiseProduct(h.color);
    G.px[k] = h.p.x(), G.py[k] = h.p.y(), G.pz[k] = h.p.z(), G.eps[k] = h.eps;
    G.gx[k] = h.ng.x(), G.gy[k] = h.ng.y(), G.gz[k] = h.ng.z();
    G.nx[k] = h.ns.x(), G.ny[k] = h.ns.y(), G.nz[k] = h.ns.z();
    G.ar[k] = base.x(), G.ag[k] = base.y(), G.ab[k] = base.z();
    PixelSampler& sampler = *samplers[k];
    sampler.start_bounce(L.depth[k], light_point);
    const Vec2f u = light_point ? sampler.uniform2(Decision::light) : Vec2f::Zero();
    const auto ls = s.lights->sample(h.p, u, 0.f);
    if (ls && ls->shadowed && std::isfinite(ls->distance)) {
      G.light[k] = -1, G.delta[k] = ls->delta ? 1.f : 0.f;
      G.wx[k] = ls->wi.x(), G.wy[k] = ls->wi.y(), G.wz[k] = ls->wi.z();
      G.lr[k] = ls->radiance.x(), G.lg[k] = ls->radiance.y(), G.lb[k] = ls->radiance.z(), G.lpdf[k] = ls->pdf;
      G.qx[k] = ls->point.x(), G.qy[k] = ls->point.y(), G.qz[k] = ls->point.z();
      G.q_eps[k] = s.traced.offset_distance(ls->point);
    }
    const Vec2f d = sampler.uniform2(Decision::direction);
    G.u1[k] = d.x(), G.u2[k] = d.y();
  }
  const int max_depth = s.max_depth;
  for (int k = 0; k < kLanes; ++k) {
    // The shading normal on wo's side (LambertBsdf).
    const float turn = (G.nx[k] * L.dx[k] + G.ny[k] * L.dy[k] + G.nz[k] * L.dz[k]) > 0 ? -1.f : 1.f;
    const float nx = turn * G.nx[k], ny = turn * G.ny[k], nz = turn * G.nz[k];
    // NEE: f cos / p_light with the power heuristic against cos / π (sample_direct).
    const float cos_i = nx * G.wx[k] + ny * G.wy[k] + nz * G.wz[k], bsdf_pdf = cos_i * kInvPi;
    // A delta light's weight is 1, the power heuristic's is at most 1: the
    // larger of the two, so that every lane divides and no branch keeps the
    // loop scalar (a light's pdf is never 0: LightSampler returns no sample then).
    const float a = G.lpdf[k] * G.lpdf[k], b = bsdf_pdf * bsdf_pdf;
    const float w = std::max(a / (a + b), G.delta[k]);
    const float scale = bsdf_pdf * w / G.lpdf[k];
    // The shadow segment from the offset hit to the light's point (EmbreeScene::shadow_segment).
    const float lx = G.qx[k] - G.px[k], ly = G.qy[k] - G.py[k], lz = G.qz[k] - G.pz[k];
    const float e = ((G.gx[k] * lx + G.gy[k] * ly + G.gz[k] * lz) >= 0 ? 1.f : -1.f) * G.eps[k];
    const float ox = G.px[k] + e * G.gx[k], oy = G.py[k] + e * G.gy[k], oz = G.pz[k] + e * G.gz[k];
    const float sx = G.qx[k] - ox, sy = G.qy[k] - oy, sz = G.qz[k] - oz;
    const float l2 = sx * sx + sy * sy + sz * sz, inv_l = 1 / std::sqrt(l2);
    const float tmax = l2 * inv_l - G.q_eps[k];
    S.sx[k] = ox, S.sy[k] = oy, S.sz[k] = oz, S.sdx[k] = sx * inv_l, S.sdy[k] = sy * inv_l, S.sdz[k] = sz * inv_l;
    S.stmax[k] = tmax;
    S.cr[k] = L.br[k] * G.ar[k] * G.lr[k] * scale, S.cg[k] = L.bg[k] * G.ag[k] * G.lg[k] * scale;
    S.cb[k] = L.bb[k] * G.ab[k] * G.lb[k] * scale;
    S.shadow[k] = G.hit[k] & G.light[k] & (cos_i > 0 ? -1 : 0) & (tmax > 0 ? -1 : 0);
    // Cosine-weighted bounce about the turned shading normal.
    float dx, dy, dz;
    cosine_bounce(nx, ny, nz, G.u1[k], G.u2[k], dx, dy, dz);
    // The next ray leaves from the side of the geometric surface it goes to (EmbreeScene::offset).
    const float f = ((G.gx[k] * dx + G.gy[k] * dy + G.gz[k] * dz) >= 0 ? 1.f : -1.f) * G.eps[k];
    L.ox[k] = G.px[k] + f * G.gx[k], L.oy[k] = G.py[k] + f * G.gy[k], L.oz[k] = G.pz[k] + f * G.gz[k];
    L.dx[k] = dx, L.dy[k] = dy, L.dz[k] = dz;
    L.br[k] *= G.ar[k], L.bg[k] *= G.ag[k], L.bb[k] *= G.ab[k];
    L.depth[k] += 1;
    const int on = (L.depth[k] < max_depth) & ((L.br[k] > 0) | (L.bg[k] > 0) | (L.bb[k] > 0));
    L.live[k] = G.hit[k] & -on;
  }
}

// Renders the pixels [begin, end) × spp, 16 paths at a time; returns the
// rays traced. film: 3 floats per pixel, summed radiance.
std::uint64_t render_lanes(const Setup& s, int begin, int end, float* film, std::vector<Packet>* record) {
  Lanes L;
  Shading S;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  const RTCScene scene = s.traced.rtc_scene();
  std::uint64_t rays = 0;
  std::int64_t next = std::int64_t(begin) * s.spp;
  const std::int64_t last = std::int64_t(end) * s.spp;
  for (int k = 0; k < kLanes; ++k) L.live[k] = 0;
  alignas(64) RTCRayHit16 rh;
  alignas(64) RTCRay16 shadow;
  std::optional<PixelSampler> samplers[kLanes];
  for (;;) {
    // Idle lanes take the next samples: camera ray, seed, throughput 1.
    for (int k = 0; k < kLanes; ++k) {
      if (L.live[k] || next == last) continue;
      const int pixel = int(next / s.spp), x = pixel % s.size, y = pixel / s.size;
      samplers[k].emplace(s.sampler, s.seed, std::uint64_t(pixel), std::uint64_t(next % s.spp));
      const Vec2f j = samplers[k]->camera_jitter();
      Vec3f o, d;
      s.camera.ray(2 * (x + j.x()) / s.size - 1, 1 - 2 * (y + j.y()) / s.size, &o, &d);
      L.ox[k] = o.x(), L.oy[k] = o.y(), L.oz[k] = o.z(), L.dx[k] = d.x(), L.dy[k] = d.y(), L.dz[k] = d.z();
      L.br[k] = L.bg[k] = L.bb[k] = 1;
      L.depth[k] = 0, L.pixel[k] = pixel, L.live[k] = -1;
      ++next;
    }
    int any = 0;
    for (int k = 0; k < kLanes; ++k) any |= L.live[k];
    if (!any) break;
    for (int k = 0; k < kLanes; ++k) {
      rh.ray.org_x[k] = L.ox[k], rh.ray.org_y[k] = L.oy[k], rh.ray.org_z[k] = L.oz[k], rh.ray.tnear[k] = 0;
      rh.ray.dir_x[k] = L.dx[k], rh.ray.dir_y[k] = L.dy[k], rh.ray.dir_z[k] = L.dz[k], rh.ray.time[k] = 0;
      rh.ray.tfar[k] = INFINITY, rh.ray.mask[k] = EmbreeScene::kCameraMask, rh.ray.id[k] = 0, rh.ray.flags[k] = 0;
    }
    int* hits = record ? record_packet(*record, L.live, rh.ray, false) : nullptr;
    const int found_surfaces = trace(s.packets, scene, &context, L.live, rh);
    if (hits) *hits = found_surfaces;
    for (int k = 0; k < kLanes; ++k) rays += L.live[k] & 1;
    if (s.lights)
      shade_general(s, rh, samplers, L, S);
    else
      shade_point_light(s, rh, samplers, L, S);
    for (int k = 0; k < kLanes; ++k) {
      shadow.org_x[k] = S.sx[k], shadow.org_y[k] = S.sy[k], shadow.org_z[k] = S.sz[k], shadow.tnear[k] = 0;
      shadow.dir_x[k] = S.sdx[k], shadow.dir_y[k] = S.sdy[k], shadow.dir_z[k] = S.sdz[k], shadow.time[k] = 0;
      shadow.tfar[k] = S.stmax[k], shadow.mask[k] = EmbreeScene::kShadowMask, shadow.id[k] = 0, shadow.flags[k] = 0;
    }
    int* blockers = record ? record_packet(*record, S.shadow, shadow, true) : nullptr;
    const int found_blockers = trace(s.packets, scene, &context, S.shadow, shadow);
    if (blockers) *blockers = found_blockers;
    for (int k = 0; k < kLanes; ++k) rays += S.shadow[k] & 1;
    // Unblocked contributions into the film (scattered by pixel).
    for (int k = 0; k < kLanes; ++k)
      if (S.shadow[k] && shadow.tfar[k] >= 0) {
        float* f = film + 3 * std::size_t(L.pixel[k] - begin);
        f[0] += S.cr[k], f[1] += S.cg[k], f[2] += S.cb[k];
      }
  }
  return rays;
}

// The complete variant (lane_paths.hpp) against PathTrace's trace_path on
// the same samples of `scene` (every pixel's samples in order), alternating,
// 1 and 2 threads: their rays per CPU second, and whether every sample's
// result (radiance, AOVs, ray counts) is the same bits. One row per thread
// count into `csv`.
void complete_against_pathtrace(const std::string& name, const Scene& scene, const RenderSettings& rs, bool quick,
                                loom::bench::Csv& csv) {
  const EmbreeScene traced(scene);
  const PathScene paths(scene, traced, rs.environment_sampling);
  const PathContext c = paths.context(rs);
  const CameraRays cam(*scene.camera, rs.width, rs.height);
  std::vector<SampleJob> jobs;
  for (std::uint32_t p = 0; p < std::uint32_t(rs.width) * std::uint32_t(rs.height); ++p)
    for (int sample = 0; sample < rs.spp; ++sample) jobs.push_back({p, sample});
  std::vector<PathResult> in_lanes(jobs.size()), one_at_a_time(jobs.size());
  constexpr std::size_t kRun = 1024;  // jobs a task takes
  const auto lanes = [&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, jobs.size(), kRun), [&](const auto& r) {
      trace_lanes(c, cam, rs.width, rs.height, jobs.data() + r.begin(), r.size(), in_lanes.data() + r.begin());
    });
  };
  const auto one_path = [&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, jobs.size(), kRun), [&](const auto& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i) {
        Vec3f origin, dir;
        PixelSampler sampler = start_sample(c, cam, rs.width, rs.height, jobs[i].pixel, jobs[i].sample, origin, dir);
        one_at_a_time[i] = trace_path(c, origin, dir, sampler);
      }
    });
  };
  const auto bits = [](const PathResult& p) {
    return std::vector<float>{p.L.x(),      p.L.y(),      p.L.z(),       p.albedo.x(),
                              p.albedo.y(), p.albedo.z(), p.normal.x(),  p.normal.y(),
                              p.normal.z(), p.depth,      float(p.rays), float(p.shadow_rays)};
  };
  for (int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    const auto t = loom::bench::time_alternating(quick ? 1 : 5, {one_path, lanes});
    std::uint64_t rays = 0;
    bool same = true;
    for (std::size_t i = 0; i < jobs.size(); ++i) {
      rays += std::uint64_t(one_at_a_time[i].rays + one_at_a_time[i].shadow_rays);
      const std::vector<float> a = bits(in_lanes[i]), b = bits(one_at_a_time[i]);
      same = same && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
    }
    const double one_rate = double(rays) / t[0].cpu, lane_rate = double(rays) / t[1].cpu;
    csv.row({name, (long long)threads, one_rate, lane_rate, lane_rate / one_rate, double(rays) / double(jobs.size()),
             std::string(same ? "yes" : "no"), loom::bench::load_average()});
    std::cout << "lanes, the complete variant on " << name << ", " << threads << " thread(s), per CPU second: "
              << "PathTrace's loop " << one_rate / 1e6 << " M rays, in lanes " << lane_rate / 1e6
              << " M: " << lane_rate / one_rate << "x; every sample the same bits: " << (same ? "yes" : "NO") << "\n";
  }
}

}  // namespace

void bench_lanes(bool quick) {
  const Scene scene = embree_cornell_box(EMBREE_MODELS);
  const EmbreeScene traced(scene);
  RenderSettings rs;  // PathTrace's settings, and the lane loop's
  rs.width = rs.height = quick ? 128 : 256;
  rs.spp = 16;
  rs.max_depth = 8;
  rs.russian_roulette = false;
  Setup s{traced,
          CameraRays(*scene.camera, rs.width, rs.height),
          rs.width,
          rs.spp,
          rs.max_depth,
          rs.sampler,
          rs.seed,
          {},
          0,
          {},
          true,
          nullptr};
  for (int i = 0; i < 3; ++i) s.light[i] = float(scene.lights.at(0).position[i]);
  s.intensity = float(scene.lights.at(0).intensity);
  std::vector<Vec3f> emission;
  for (const TracedObject& o : traced.objects()) {
    const Material& m = scene.objects[std::size_t(o.scene_index)].material;
    s.base.push_back(m.base_color.cast<float>());
    emission.push_back(m.emission.cast<float>());
  }
  // The general variant: PathTrace's light sampler and hit assembly.
  const EnvironmentLight environment(scene.environment, rs.environment_sampling);
  const LightSampler lights(scene, traced, emission, environment);
  Setup s_general = s;
  s_general.lights = &lights;
  const int pixels = s.size * s.size;
  std::vector<float> film(3 * std::size_t(pixels));
  // Renders the image with the lane loop into `film`; returns the rays.
  const auto render_image = [&](const Setup& setup) {
    std::fill(film.begin(), film.end(), 0.f);
    std::atomic<std::uint64_t> rays{0};
    tbb::parallel_for(tbb::blocked_range<int>(0, pixels, 1024), [&](const tbb::blocked_range<int>& r) {
      rays += render_lanes(setup, r.begin(), r.end(), film.data() + 3 * std::size_t(r.begin()), nullptr);
    });
    return std::uint64_t(rays);
  };
  const auto film_image = [&] { return cv::Mat(cv::Mat(s.size, s.size, CV_32FC3, film.data()) / float(s.spp)); };
  // The packets of one sample per pixel, for the replay; their rays, and how many found something.
  struct Recorded {
    std::vector<Packet> packets;
    std::uint64_t rays = 0, found = 0;
  };
  const auto record_one_sample = [&](const Setup& setup) {
    Recorded r;
    Setup one = setup;
    one.spp = 1;
    render_lanes(one, 0, pixels, film.data(), &r.packets);
    for (const Packet& p : r.packets) {
      for (int k = 0; k < kLanes; ++k) r.rays += p.valid[k] & 1;
      r.found += std::uint64_t(p.found);
    }
    return r;
  };
  const Recorded recorded_lanes = record_one_sample(s), recorded_general = record_one_sample(s_general);
  const std::vector<Packet>& recorded = recorded_lanes.packets;
  const std::uint64_t recorded_rays = recorded_lanes.rays, recorded_found = recorded_lanes.found;
  const RTCScene rtc = traced.rtc_scene();
  // Embree alone on recorded packets: as packets, or one ray per call.
  // Returns how many rays found a surface or a blocker.
  const auto replay_packets = [&](const std::vector<Packet>& recorded, bool packets) {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, recorded.size(), 256), std::uint64_t(0),
        [&](const tbb::blocked_range<std::size_t>& r, std::uint64_t found) {
          RTCIntersectContext context;
          rtcInitIntersectContext(&context);
          for (std::size_t i = r.begin(); i != r.end(); ++i) {
            const Packet& p = recorded[i];
            if (p.shadow) {
              RTCRay16 ray = p.rays;
              found += std::uint64_t(trace(packets, rtc, &context, p.valid, ray));
            } else {
              RTCRayHit16 h;
              h.ray = p.rays;
              found += std::uint64_t(trace(packets, rtc, &context, p.valid, h));
            }
          }
          return found;
        },
        [](std::uint64_t a, std::uint64_t b) { return a + b; });
  };
  const auto replay = [&](bool packets) { return replay_packets(recorded, packets); };
  // The estimator checked: both 16-spp images against PathTrace's converged one.
  RenderSettings reference_settings = rs;
  reference_settings.spp = quick ? 64 : 512;
  reference_settings.seed = 99;
  const cv::Mat reference = render(scene, *scene.camera, traced, reference_settings).image;
  // Both with independent samples too (untimed).
  RenderSettings independent = rs;
  independent.sampler = SamplerKind::independent;
  const double error_independent = rel_mse(render(scene, *scene.camera, traced, independent).image, reference);
  Setup s_independent = s;
  s_independent.sampler = SamplerKind::independent;
  render_image(s_independent);
  const double error_lanes_independent = rel_mse(film_image(), reference);
  const int passes = s.spp;  // the replay traces as many rays as a render
  loom::bench::Csv csv("pathtrace_lanes", {"threads",
                                           "pathtrace_rays_per_cpu_s",
                                           "lanes_rays_per_cpu_s",
                                           "embree_one_rays_per_cpu_s",
                                           "embree_packets_rays_per_cpu_s",
                                           "lanes_fraction_of_one",
                                           "lanes_fraction_of_packets",
                                           "lanes_rays_per_path",
                                           "pathtrace_rays_per_path",
                                           "lanes_mean",
                                           "pathtrace_mean",
                                           "lanes_relmse",
                                           "pathtrace_relmse",
                                           "lanes_relmse_to_pathtrace_same_samples",
                                           "lanes_independent_relmse",
                                           "pathtrace_independent_relmse",
                                           "outcomes_match",
                                           "lanes_one_call_rays_per_cpu_s",
                                           "lanes_one_call_fraction_of_one",
                                           "general_rays_per_cpu_s",
                                           "embree_general_packets_rays_per_cpu_s",
                                           "general_fraction_of_packets",
                                           "general_rays_per_path",
                                           "general_relmse",
                                           "general_relmse_to_pathtrace_same_samples",
                                           "load1"});
  Setup s_one_call = s;  // the same loop, each ray in a call of its own
  s_one_call.packets = false;
  for (int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    std::uint64_t rays = 0;
    RenderResult ours;
    bool same_one = true, same_packets = true;
    const auto lanes = [&] { rays = render_image(s); };
    std::uint64_t rays_one_call = 0;
    const auto lanes_one_call = [&] { rays_one_call = render_image(s_one_call); };
    const auto pathtrace = [&] { ours = render(scene, *scene.camera, traced, rs); };
    const auto embree_one = [&] {
      for (int p = 0; p < passes; ++p) same_one = replay(false) == recorded_found && same_one;
    };
    const auto embree_packets = [&] {
      for (int p = 0; p < passes; ++p) same_packets = replay(true) == recorded_found && same_packets;
    };
    std::uint64_t rays_general = 0;
    const auto general = [&] { rays_general = render_image(s_general); };
    const auto embree_general = [&] {
      for (int p = 0; p < passes; ++p)
        same_packets = replay_packets(recorded_general.packets, true) == recorded_general.found && same_packets;
    };
    const auto t = loom::bench::time_alternating(
        quick ? 1 : 5, {pathtrace, lanes_one_call, embree_one, embree_packets, general, embree_general, lanes});
    double mean_lanes = 0;
    for (float v : film) mean_lanes += v;
    mean_lanes /= double(film.size()) * s.spp;
    const cv::Mat lane_image = film_image();
    const double error_lanes = rel_mse(lane_image, reference), error_ours = rel_mse(ours.image, reference);
    const double lanes_to_ours = rel_mse(lane_image, ours.image);  // the same samples: rounding apart
    // The general variant's image, untimed.
    render_image(s_general);
    const double error_general = rel_mse(film_image(), reference), general_to_ours = rel_mse(film_image(), ours.image);
    const cv::Scalar m = cv::mean(ours.image);
    const double mean_ours = (m[0] + m[1] + m[2]) / 3;
    const double replayed = double(recorded_rays) * passes;
    const double general_rate = double(rays_general) / t[4].cpu;
    const double general_packet_rate = double(recorded_general.rays) * passes / t[5].cpu;
    const double lane_rate = double(rays) / t[6].cpu, one_rate = replayed / t[2].cpu, packet_rate = replayed / t[3].cpu;
    const double one_call_rate = double(rays_one_call) / t[1].cpu;
    const double pathtrace_rate = double(ours.rays) / t[0].cpu;
    csv.row({(long long)threads,
             pathtrace_rate,
             lane_rate,
             one_rate,
             packet_rate,
             lane_rate / one_rate,
             lane_rate / packet_rate,
             double(rays) / double(pixels) / s.spp,
             double(ours.rays) / double(ours.paths),
             mean_lanes,
             mean_ours,
             error_lanes,
             error_ours,
             lanes_to_ours,
             error_lanes_independent,
             error_independent,
             std::string(same_one && same_packets ? "yes" : "no"),
             one_call_rate,
             one_call_rate / one_rate,
             general_rate,
             general_packet_rate,
             general_rate / general_packet_rate,
             double(rays_general) / double(pixels) / s.spp,
             error_general,
             general_to_ours,
             loom::bench::load_average()});
    std::cout << "lanes, " << threads << " thread(s), per CPU second: PathTrace " << pathtrace_rate / 1e6
              << " M rays, the lane loop " << lane_rate / 1e6 << " M; Embree alone on the lane loop's rays "
              << one_rate / 1e6 << " M one per call, " << packet_rate / 1e6 << " M in its packets: the lane loop at "
              << lane_rate / one_rate << " / " << lane_rate / packet_rate << " of them"
              << (same_one && same_packets ? "" : " (REPLAY FOUND OTHER HITS)") << "; rays per path "
              << double(rays) / double(pixels) / s.spp << " (PathTrace " << double(ours.rays) / double(ours.paths)
              << "), image mean " << mean_lanes << " (PathTrace " << mean_ours << "), relMSE against PathTrace at "
              << reference_settings.spp << " spp " << error_lanes << " (PathTrace " << error_ours
              << "; with independent samples " << error_lanes_independent << " and " << error_independent
              << "), relMSE against PathTrace's image of the same samples " << lanes_to_ours
              << "; with one ray per call " << one_call_rate / 1e6 << " M rays, " << one_call_rate / one_rate
              << " of Embree alone one per call; the general variant " << general_rate / 1e6 << " M rays, "
              << general_rate / general_packet_rate << " of Embree alone on its packets (" << general_packet_rate / 1e6
              << " M), relMSE " << error_general << ", against PathTrace's image " << general_to_ours << "\n";
    if (threads == 2) {  // the two images of the same samples, to look at side by side
      cv::Mat side;
      cv::hconcat(ours.image, lane_image, side);
      save_png(side, "lanes-pathtrace-and-lane-loop.png");
    }
  }
  csv.save();
  // The complete variant: on the same box, and on the plugin's box with a
  // mirror and a glass ball (their bounces take the scalar step in their lane).
  loom::bench::Csv complete("pathtrace_lanes_complete",
                            {"scene", "threads", "pathtrace_loop_rays_per_cpu_s", "lanes_rays_per_cpu_s",
                             "lanes_over_pathtrace_loop", "rays_per_path", "same_bits", "load1"});
  complete_against_pathtrace("Embree's box", scene, rs, quick, complete);
  CornellBoxOptions balls;
  balls.contents = CornellContents::spheres;
  complete_against_pathtrace("the box with a mirror and a glass ball", cornell_box(balls), rs, quick, complete);
  complete.save();
}

}  // namespace loom::pathtrace::bench
