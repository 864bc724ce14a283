// An experiment (issue 39), not a renderer: PathTrace's whole path loop,
// 16 paths at a time. Each step's rays go to Embree as one 16-ray packet
// (rtcIntersect16, rtcOccluded16), and the bounces at Lambertian surfaces
// without a normal map (next-event estimation's BSDF term and MIS weight,
// the cosine-weighted direction, its frame and normalization, the
// throughput) run in SSE lanes, four paths an instruction. Everything else
// a path does (the hit, emission, the light sample, the environment, other
// materials, roulette, the AOVs) is PathTrace's own scalar step
// (path_loop.hpp), lane by lane. The lane arithmetic is PathTrace's,
// operation for operation, so a sample gives the same bits as trace_path.
#pragma once

#include <cstddef>
#include <cstdint>

#include "camera_rays.hpp"
#include "path_loop.hpp"

namespace loom::pathtrace::bench {

constexpr int kLanes = 16;

// A packet's valid rays traced as one packet (rtcIntersect16) or one ray per
// call (rtcIntersect1, results written back into the packet); its hits'
// geometry ids are reset first. Returns how many found a surface.
int trace(bool as_packet, RTCScene scene, RTCIntersectContext* context, const int* valid, RTCRayHit16& packet);
// The same for shadow rays (rtcOccluded16 / rtcOccluded1); returns how many
// found a blocker.
int trace(bool as_packet, RTCScene scene, RTCIntersectContext* context, const int* valid, RTCRay16& rays);

// One sample to trace: the pixel's index in the image and the sample's number.
struct SampleJob {
  std::uint32_t pixel;
  int sample;
};

// Traces jobs[0, n), 16 paths in flight, a finished path's lane taking the
// next job at once; results[i] is jobs[i]'s path.
void trace_lanes(const PathContext& c, const CameraRays& cam, int width, int height, const SampleJob* jobs,
                 std::size_t n, PathResult* results);

}  // namespace loom::pathtrace::bench
