// The limit of the path tracer's ray cost: Embree alone, on the same BVH and
// thread count, tracing the rays PathTrace casts (issue 27, "The limit").
#pragma once

namespace loom::pathtrace::bench {

// `bench_pathtrace rays`: on Embree's Cornell box (the `embree` mode's scene:
// Lambertian walls, one point light, depth 8, no roulette) records the rays
// of a sample of paths (camera, bounce and shadow rays, in the order a path
// casts them), then times, alternating, PathTrace's render and
// rtcIntersect1 / rtcOccluded1 over the recorded rays in a tight loop, and
// the same rays in 16-ray packets, with 1 and 2 threads. Beside them the
// peer, measured alike: Embree's tutorial path tracer on the same box, its
// rays recorded by embree_ray_log.cpp and replayed on the same BVH (when
// embree-tools is installed). Then PathTrace alone on the box with a ball of
// 2M triangles. Writes pathtrace_rays.csv: per scene and thread count the
// ray rates and each path tracer's fraction of Embree's (the share of its
// time that is Embree's traversal).
void bench_ray_rate(bool quick);

}  // namespace loom::pathtrace::bench
