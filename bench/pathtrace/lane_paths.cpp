#include "lane_paths.hpp"

#include <emmintrin.h>

#include <optional>

namespace loom::pathtrace::bench {

namespace {

// Four lanes of floats and of masks (-1 or 0), in GCC's vector extensions:
// +, -, *, / and comparisons work lane by lane, as SSE2 instructions.
using F4 = float __attribute__((vector_size(16)));
using I4 = int __attribute__((vector_size(16)));

F4 load(const float* p) { return F4{p[0], p[1], p[2], p[3]}; }
I4 load(const int* p) { return I4{p[0], p[1], p[2], p[3]}; }
void store(float* p, F4 v) {
  for (int i = 0; i < 4; ++i) p[i] = v[i];
}
void store(int* p, I4 v) {
  for (int i = 0; i < 4; ++i) p[i] = v[i];
}
F4 splat(float x) { return F4{x, x, x, x}; }
F4 select(I4 mask, F4 a, F4 b) { return F4(((I4)a & mask) | ((I4)b & ~mask)); }

// Eigen's order for a 3-vector's sum of products: a0 b0 + (a1 b1 + a2 b2).
F4 dot(F4 ax, F4 ay, F4 az, F4 bx, F4 by, F4 bz) { return ax * bx + (ay * by + az * bz); }

// sampling.hpp's inv_sqrt, four at a time (the same estimate, the same Newton step).
F4 inv_sqrt(F4 x) {
  const F4 r = F4(_mm_rsqrt_ps(__m128(x)));
  return r * (1.5f - 0.5f * x * r * r);
}

// sampling.hpp's cos_sin_2pi, four at a time: the quadrant's switch as selects.
void cos_sin_2pi(F4 t, F4& c, F4& s) {
  const I4 q = __builtin_convertvector(4 * t + 0.5f, I4);  // t >= 0: truncation rounds
  const F4 a = (4 * t - __builtin_convertvector(q, F4)) * (kPi / 2);
  const F4 a2 = a * a;
  const F4 sa = a * (1 + a2 * (-1.f / 6 + a2 * (1.f / 120 + a2 * (-1.f / 5040 + a2 * (1.f / 362880)))));
  const F4 ca = 1 + a2 * (-0.5f + a2 * (1.f / 24 + a2 * (-1.f / 720 + a2 * (1.f / 40320 - a2 * (1.f / 3628800)))));
  const I4 qq = q & 3;
  const I4 q0 = qq == 0, q1 = qq == 1, q2 = qq == 2;
  c = select(q0, ca, select(q1, -sa, select(q2, -ca, sa)));
  s = select(q0, sa, select(q1, ca, select(q2, -sa, -ca)));
}

// Whether Embree's 16-ray packets find, bit for bit, what its single rays
// find in this scene: for triangles they do (the same hits, t, u, v and
// normals, over 300k hits of the benchmark's boxes), for sphere points not
// (t differs in the last bit), so a scene with spheres traces each lane's
// ray alone.
bool packets_match_single_rays(const EmbreeScene& traced) {
  for (const TracedObject& o : traced.objects())
    if (o.spheres) return false;
  return true;
}

// A lane's path, as path_loop.hpp's steps keep it.
struct Lane {
  std::optional<PixelSampler> sampler;
  PathResult r;
  PathVertex v;
  Vec3f origin;
  SurfaceHit hit;
  LightSample light;  // what add_light reads of the bounce's light sample
  PendingShadow shadow;
  std::size_t job = 0;
  int depth = 0;
  bool live = false;
};

// What the Lambertian bounce of the lanes in `lambert` reads and writes, one
// array of 16 per quantity.
struct LambertLanes {
  alignas(16) float nx[kLanes], ny[kLanes], nz[kLanes];  // the shading normal
  alignas(16) float dx[kLanes], dy[kLanes], dz[kLanes];  // the ray that arrived; then the bounce's direction
  alignas(16) float gx[kLanes], gy[kLanes], gz[kLanes];  // the geometric normal
  alignas(16) float br[kLanes], bg[kLanes], bb[kLanes];  // the throughput; then times the base colour
  alignas(16) float ar[kLanes], ag[kLanes], ab[kLanes];  // the base colour
  alignas(16) float wx[kLanes], wy[kLanes], wz[kLanes];  // the light sample's direction
  alignas(16) float lr[kLanes], lg[kLanes], lb[kLanes], lpdf[kLanes];
  alignas(16) float u1[kLanes], u2[kLanes];  // the bounce's pair
  alignas(16) int lit[kLanes], delta[kLanes];
  // Out: the light's contribution, the bounce's pdf, and masks.
  alignas(16) float cr[kLanes], cg[kLanes], cb[kLanes], pdf[kLanes];
  alignas(16) int adds_light[kLanes], bounces[kLanes];
  bool lambert[kLanes];
};

// path_loop.cpp's sample_direct and LambertBsdf for the lanes, operation for
// operation: the shading normal turned to wo's side; the light's term
// cos θi / π, the side test, the power heuristic and β f Le w / p; Malley's
// cosine-weighted direction in Duff et al.'s frame, normalized. Lanes
// outside the bounce compute on what they hold; their results are not read.
void lambert_bounce(LambertLanes& l, bool mis) {
  for (int i = 0; i < kLanes; i += 4) {
    F4 nx = load(l.nx + i), ny = load(l.ny + i), nz = load(l.nz + i);
    const F4 dx = load(l.dx + i), dy = load(l.dy + i), dz = load(l.dz + i);
    const I4 turn = dot(nx, ny, nz, dx, dy, dz) > 0;
    nx = select(turn, -nx, nx), ny = select(turn, -ny, ny), nz = select(turn, -nz, nz);
    const F4 br = load(l.br + i), bg = load(l.bg + i), bb = load(l.bb + i);
    const F4 ar = load(l.ar + i), ag = load(l.ag + i), ab = load(l.ab + i);
    // Next-event estimation.
    const F4 wx = load(l.wx + i), wy = load(l.wy + i), wz = load(l.wz + i), lpdf = load(l.lpdf + i);
    const F4 cos_i = dot(nx, ny, nz, wx, wy, wz), scale = cos_i * kInvPi;
    const I4 side = 0.f * dot(wx, wy, wz, load(l.gx + i), load(l.gy + i), load(l.gz + i)) >= 0;
    const F4 a = lpdf * lpdf, b = scale * scale;
    const F4 heuristic = select(a > 0, select(a == kInf, splat(1), a / (a + b)), splat(0));
    const I4 full = mis ? load(l.delta + i) : I4{-1, -1, -1, -1};
    const F4 s = scale * select(full, splat(1), heuristic) / lpdf;
    store(l.cr + i, br * ar * load(l.lr + i) * s);
    store(l.cg + i, bg * ag * load(l.lg + i) * s);
    store(l.cb + i, bb * ab * load(l.lb + i) * s);
    store(l.adds_light + i, load(l.lit + i) & (cos_i > 0) & side);
    // The bounce: wi about +z, then into the world by the normal's frame.
    const F4 u1 = load(l.u1 + i);
    const F4 r = F4(_mm_sqrt_ps(__m128(u1))), z = F4(_mm_sqrt_ps(__m128(1 - u1)));
    F4 c, sn;
    cos_sin_2pi(load(l.u2 + i), c, sn);
    const F4 xl = r * c, yl = r * sn;
    const F4 sign = F4(((I4)nz & (int)0x80000000) | (I4)splat(1));  // copysign(1, n.z)
    const F4 fa = -1 / (sign + nz), fb = nx * ny * fa;
    const F4 sx = 1 + sign * nx * nx * fa, sy = sign * fb, sz = -sign * nx;
    const F4 tx = fb, ty = sign + ny * ny * fa, tz = -ny;
    const F4 ox = xl * sx + yl * tx + z * nx, oy = xl * sy + yl * ty + z * ny, oz = xl * sz + yl * tz + z * nz;
    const F4 inv = inv_sqrt(dot(ox, oy, oz, ox, oy, oz));
    store(l.dx + i, ox * inv), store(l.dy + i, oy * inv), store(l.dz + i, oz * inv);
    store(l.pdf + i, z * kInvPi);
    store(l.bounces + i, z > 0);
    store(l.br + i, br * ar), store(l.bg + i, bg * ag), store(l.bb + i, bb * ab);
  }
}

}  // namespace

int trace(bool as_packet, RTCScene scene, RTCIntersectContext* context, const int* valid, RTCRayHit16& packet) {
  for (int k = 0; k < kLanes; ++k)
    packet.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID, packet.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
  if (as_packet) rtcIntersect16(valid, scene, context, &packet);
  for (int k = 0; k < kLanes && !as_packet; ++k) {
    if (!valid[k]) continue;
    RTCRayHit h;
    h.ray = {packet.ray.org_x[k], packet.ray.org_y[k], packet.ray.org_z[k], packet.ray.tnear[k],
             packet.ray.dir_x[k], packet.ray.dir_y[k], packet.ray.dir_z[k], packet.ray.time[k],
             packet.ray.tfar[k],  packet.ray.mask[k],  packet.ray.id[k],    packet.ray.flags[k]};
    h.hit.geomID = RTC_INVALID_GEOMETRY_ID, h.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, context, &h);
    packet.ray.tfar[k] = h.ray.tfar;
    packet.hit.Ng_x[k] = h.hit.Ng_x, packet.hit.Ng_y[k] = h.hit.Ng_y, packet.hit.Ng_z[k] = h.hit.Ng_z;
    packet.hit.u[k] = h.hit.u, packet.hit.v[k] = h.hit.v;
    packet.hit.geomID[k] = h.hit.geomID, packet.hit.primID[k] = h.hit.primID;
  }
  int found = 0;
  for (int k = 0; k < kLanes; ++k) found += valid[k] && packet.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
  return found;
}

int trace(bool as_packet, RTCScene scene, RTCIntersectContext* context, const int* valid, RTCRay16& rays) {
  if (as_packet) rtcOccluded16(valid, scene, context, &rays);
  for (int k = 0; k < kLanes && !as_packet; ++k) {
    if (!valid[k]) continue;
    RTCRay r{rays.org_x[k], rays.org_y[k], rays.org_z[k], rays.tnear[k], rays.dir_x[k], rays.dir_y[k],
             rays.dir_z[k], rays.time[k],  rays.tfar[k],  rays.mask[k],  rays.id[k],    rays.flags[k]};
    rtcOccluded1(scene, context, &r);
    rays.tfar[k] = r.tfar;
  }
  int found = 0;
  for (int k = 0; k < kLanes; ++k) found += valid[k] && rays.tfar[k] < 0;
  return found;
}

void trace_lanes(const PathContext& c, const CameraRays& cam, int width, int height, const SampleJob* jobs,
                 std::size_t n, PathResult* results) {
  const Strategies use = strategies(c);
  const bool light_point = use.nee && c.lights.reads_point();
  const RTCScene scene = c.traced.rtc_scene();
  const bool packets = packets_match_single_rays(c.traced);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  Lane lanes[kLanes];
  alignas(64) RTCRayHit16 packet;
  alignas(64) RTCRay16 shadows;
  alignas(64) int valid[kLanes], shadowed[kLanes];
  LambertLanes l;
  const auto finish = [&](Lane& lane) {
    results[lane.job] = lane.r;
    lane.live = false;
  };
  std::size_t next = 0;
  for (;;) {
    // Idle lanes take the next samples.
    bool any = false;
    for (Lane& lane : lanes) {
      if (!lane.live && next < n) {
        const SampleJob job = jobs[next];
        PathVertex v;
        lane.sampler.emplace(start_sample(c, cam, width, height, job.pixel, job.sample, lane.origin, v.dir));
        v.prev_point = lane.origin;
        lane.v = v;
        lane.r = PathResult{};
        lane.job = next++;
        lane.depth = 0;
        lane.live = true;
      }
      any |= lane.live;
    }
    if (!any) return;
    // Their rays, as one packet.
    for (int k = 0; k < kLanes; ++k) {
      Lane& lane = lanes[k];
      valid[k] = lane.live ? -1 : 0;
      packet.ray.org_x[k] = lane.origin.x(), packet.ray.org_y[k] = lane.origin.y();
      packet.ray.org_z[k] = lane.origin.z(), packet.ray.tnear[k] = 0;
      packet.ray.dir_x[k] = lane.v.dir.x(), packet.ray.dir_y[k] = lane.v.dir.y();
      packet.ray.dir_z[k] = lane.v.dir.z(), packet.ray.time[k] = 0;
      packet.ray.tfar[k] = kInf, packet.ray.mask[k] = EmbreeScene::kCameraMask;
      packet.ray.id[k] = 0, packet.ray.flags[k] = 0;
      if (!lane.live) continue;
      ++lane.r.rays;
      lane.sampler->start_bounce(lane.depth, light_point);
    }
    trace(packets, scene, &context, valid, packet);
    // Each hit, lane by lane: what the path arrived at, and either the
    // scalar bounce (other materials, normal maps) or what the Lambertian
    // bounce in lanes reads.
    for (int k = 0; k < kLanes; ++k) {
      Lane& lane = lanes[k];
      l.lambert[k] = false;
      if (!lane.live) continue;
      if (packet.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) {
        add_environment(c, lane.v, use, lane.depth, lane.r);
        finish(lane);
        continue;
      }
      SurfaceHit& hit = lane.hit;
      c.traced.surface_hit(lane.origin, lane.v.dir, packet.ray.tfar[k], packet.hit.geomID[k], packet.hit.primID[k],
                           packet.hit.u[k], packet.hit.v[k], &hit);
      float wo_side;
      const Vec3f base = arrive(c, use, lane.v, lane.depth, hit, lane.r, wo_side);
      if (lane.depth >= c.settings.max_depth) {
        finish(lane);
        continue;
      }
      const ObjectShading& sh = c.shading[std::size_t(hit.object)];
      if (!sh.lambert || wo_side != 0) {
        if (scatter(c, hit, wo_side, sh, base, use, *lane.sampler, lane.v, lane.r) &&
            next_ray(c, hit, lane.depth, *lane.sampler, lane.v, lane.origin))
          ++lane.depth;
        else
          finish(lane);
        continue;
      }
      l.lambert[k] = true;
      l.nx[k] = hit.ns.x(), l.ny[k] = hit.ns.y(), l.nz[k] = hit.ns.z();
      l.dx[k] = lane.v.dir.x(), l.dy[k] = lane.v.dir.y(), l.dz[k] = lane.v.dir.z();
      l.gx[k] = hit.ng.x(), l.gy[k] = hit.ng.y(), l.gz[k] = hit.ng.z();
      l.br[k] = lane.v.beta.x(), l.bg[k] = lane.v.beta.y(), l.bb[k] = lane.v.beta.z();
      l.ar[k] = base.x(), l.ag[k] = base.y(), l.ab[k] = base.z();
      // The light sample's fields one by one: copied whole, its two flags
      // are read as one 2-byte load from the callee's two 1-byte stores,
      // which the core cannot forward (a stall of ~12 cycles a bounce).
      const std::optional<LightSample> sampled = use.nee ? sample_light(c, hit, *lane.sampler) : std::nullopt;
      const LightSample* ls = sampled ? &*sampled : nullptr;
      if (ls) {
        lane.light.wi = ls->wi, lane.light.distance = ls->distance, lane.light.point = ls->point;
        lane.light.shadowed = ls->shadowed;
      }
      l.lit[k] = ls ? -1 : 0;
      l.delta[k] = ls && ls->delta ? -1 : 0;
      l.wx[k] = ls ? ls->wi.x() : 0, l.wy[k] = ls ? ls->wi.y() : 0, l.wz[k] = ls ? ls->wi.z() : 0;
      l.lr[k] = ls ? ls->radiance.x() : 0, l.lg[k] = ls ? ls->radiance.y() : 0, l.lb[k] = ls ? ls->radiance.z() : 0;
      l.lpdf[k] = ls ? ls->pdf : 1;
      const Vec2f u = lane.sampler->uniform2(Decision::direction);
      l.u1[k] = u.x(), l.u2[k] = u.y();
    }
    lambert_bounce(l, use.mis);
    // The light each Lambertian lane adds, and its shadow rays as one packet.
    for (int k = 0; k < kLanes; ++k) {
      Lane& lane = lanes[k];
      lane.shadow.pending = false;
      if (l.lambert[k] && l.adds_light[k])
        add_light(c, lane.hit, lane.light, Vec3f(l.cr[k], l.cg[k], l.cb[k]), lane.r, lane.shadow);
      const EmbreeScene::Segment& s = lane.shadow.ray;
      shadowed[k] = lane.shadow.pending ? -1 : 0;
      shadows.org_x[k] = s.origin.x(), shadows.org_y[k] = s.origin.y(), shadows.org_z[k] = s.origin.z();
      shadows.dir_x[k] = s.direction.x(), shadows.dir_y[k] = s.direction.y(), shadows.dir_z[k] = s.direction.z();
      shadows.tnear[k] = 0, shadows.time[k] = 0, shadows.tfar[k] = s.tmax;
      shadows.mask[k] = EmbreeScene::kShadowMask, shadows.id[k] = 0, shadows.flags[k] = 0;
    }
    trace(packets, scene, &context, shadowed, shadows);
    // The bounce's direction, and the next ray. (scatter's test of the
    // direction against wo's side cuts nothing here: these lanes have no
    // normal map, wo_side is 0.)
    for (int k = 0; k < kLanes; ++k) {
      if (!l.lambert[k]) continue;
      Lane& lane = lanes[k];
      if (lane.shadow.pending && shadows.tfar[k] >= 0) lane.r.L += lane.shadow.L;
      if (!l.bounces[k]) {
        finish(lane);
        continue;
      }
      PathVertex& v = lane.v;
      v.beta = Vec3f(l.br[k], l.bg[k], l.bb[k]);
      v.prev_pdf = l.pdf[k];
      v.prev_delta = false;
      v.dir = Vec3f(l.dx[k], l.dy[k], l.dz[k]);
      if (next_ray(c, lane.hit, lane.depth, *lane.sampler, v, lane.origin))
        ++lane.depth;
      else
        finish(lane);
    }
  }
}

}  // namespace loom::pathtrace::bench
