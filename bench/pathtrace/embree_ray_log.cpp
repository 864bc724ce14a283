// Records the rays another program hands Embree, to time Embree alone on
// them (`bench_pathtrace rays`: Embree's tutorial path tracer on its own rays,
// beside PathTrace on its own). Loaded with LD_PRELOAD into a program linked
// against libembree3: rtcIntersect1 and rtcOccluded1 are passed on to
// Embree's own, unchanged, and each call's ray, context flags and outcome are
// kept; at exit they are written to the file $LOOM_EMBREE_RAY_LOG as
// embree_ray_log.hpp describes. Only for recording: the calls pay a lock and
// a copy, so the program is timed in a separate run without it.
#include <dlfcn.h>

#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <vector>

#include "embree_ray_log.hpp"

namespace {

using Intersect1 = void (*)(RTCScene, RTCIntersectContext*, RTCRayHit*);
using Occluded1 = void (*)(RTCScene, RTCIntersectContext*, RTCRay*);

struct Log {
  std::mutex mutex;
  std::vector<loom::pathtrace::bench::LoggedRay> rays;

  void add(const RTCRay& ray, const RTCIntersectContext* context, bool shadow, bool found) {
    const std::lock_guard<std::mutex> lock(mutex);
    rays.push_back({ray, context ? unsigned(context->flags) : 0u, shadow, found});
  }

  ~Log() {
    const char* path = std::getenv("LOOM_EMBREE_RAY_LOG");
    if (!path) return;
    std::FILE* f = std::fopen(path, "wb");
    if (!f) return;
    const bool written = std::fwrite(rays.data(), sizeof(rays[0]), rays.size(), f) == rays.size();
    if (std::fclose(f) != 0 || !written) std::remove(path);  // no half-written log
  }
};

Log& ray_log() {
  static Log instance;
  return instance;
}

template <class F>
F embree_function(const char* name) {
  const F f = reinterpret_cast<F>(dlsym(RTLD_NEXT, name));
  if (!f) {
    std::fprintf(stderr, "embree_ray_log: %s not found after this library\n", name);
    std::abort();
  }
  return f;
}

}  // namespace

extern "C" {

void rtcIntersect1(RTCScene scene, RTCIntersectContext* context, RTCRayHit* rayhit) {
  static const Intersect1 intersect = embree_function<Intersect1>("rtcIntersect1");
  const RTCRay ray = rayhit->ray;
  intersect(scene, context, rayhit);
  ray_log().add(ray, context, false, rayhit->hit.geomID != RTC_INVALID_GEOMETRY_ID);
}

void rtcOccluded1(RTCScene scene, RTCIntersectContext* context, RTCRay* ray) {
  static const Occluded1 occluded = embree_function<Occluded1>("rtcOccluded1");
  const RTCRay before = *ray;
  occluded(scene, context, ray);
  ray_log().add(before, context, true, ray->tfar < 0);
}

}  // extern "C"
