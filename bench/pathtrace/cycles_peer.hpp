// Blender's Cycles as a peer (`bench_pathtrace cycles`): the same scenes
// rendered headless by `blender -b --factory-startup -P cycles_render.py`,
// side by side with PathTrace in one run, relMSE against each renderer's own
// high-spp reference per second of rendering, and the time each needs to
// reach the same error.
#pragma once

namespace loom::pathtrace::bench {

// Skips with a note when `blender` is not on PATH (scripts/bench --cycles
// installs it). `quick`: a quarter of the reference samples, one round.
void bench_cycles(bool quick);

}  // namespace loom::pathtrace::bench
