// Embree's tutorial path tracer (Debian embree-tools `pathtracer`, the C++
// tutorial: one path at a time through rtcIntersect1 / rtcOccluded1) run as a
// separate process on its cornell_box model, for the `embree` and `rays` modes.
#pragma once

#include <filesystem>
#include <string>

namespace loom::pathtrace::bench {

// Whether `pathtracer` and its cornell_box.ecs are installed.
bool embree_tutorial_installed();

// A scratch file for the tutorial's image or ray log, named for this process
// (temp directory, loom-bench-embree-<pid><suffix>), so that two benchmarks
// running at once do not share it.
std::filesystem::path tutorial_scratch(const std::string& suffix);

// Renders cornell_box.ecs at size², spp samples, max path length depth, into
// the PFM `out`; `environment` is put before the command (VAR=value ...).
// Returns its wall seconds (negative when it failed), its CPU seconds in *cpu.
double run_embree_tutorial(int size, int spp, int depth, int threads, const std::filesystem::path& out,
                           double* cpu = nullptr, const std::string& environment = "");

// Its time for size² × spp paths alone, without loading the model and
// building its BVH: the marginal cost (t(spp) - t(1)) · spp / (spp - 1) of two
// runs into `out`, in wall and CPU seconds.
struct TutorialSeconds {
  double wall, cpu;
};
TutorialSeconds time_embree_tutorial(int size, int spp, int depth, int threads, const std::filesystem::path& out);

}  // namespace loom::pathtrace::bench
