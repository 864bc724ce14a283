// An experiment, not a renderer: the path loop of the `rays` mode's scene
// (Lambertian walls, one point light, depth 8, no roulette) with 16 paths in
// SIMD lanes and Embree's 16-ray packets, drawing PathTrace's own samples, to
// measure what shading in lanes would give against Embree's own ray rate
// (issue 39, item 4). Two variants: one reduced to this scene (the hit's
// geometric normal, an albedo per geometry, the point light in the loop),
// and a general one that takes each hit from PathTrace's hit assembly and
// its light sample from PathTrace's light sampler, one lane at a time, and
// draws the same paths as PathTrace (its image equals PathTrace's to rounding).
#pragma once

namespace loom::pathtrace::bench {

// `bench_pathtrace lanes`: PathTrace's render, the lane loop (with packets,
// and with one ray per call), the general variant, and Embree alone on each
// one's packets (the lane loop's also one ray per call), alternating, 1 and
// 2 threads. Writes pathtrace_lanes.csv: the rates, and the images' errors
// against PathTrace's.
void bench_lanes(bool quick);

}  // namespace loom::pathtrace::bench
