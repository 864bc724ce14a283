// MergeScenes: objects and lights of every linked scene, in input order; the
// last camera and environment given win.
#include "loom/plugin.hpp"
#include "loom/scene.hpp"

namespace {

constexpr const char* kInputs[] = {"a", "b", "c", "d", "e", "f", "g", "h"};

struct MergeScenes {
  static constexpr const char* name = "MergeScenes";
  static void declare(loom::NodeSpec& s) {
    s.describe("Merges up to eight scenes: objects and lights are concatenated in input order; "
               "the last camera and environment given win (with a warning when two are given).");
    for (const char* n : kInputs) s.input<loom::Scene>(n, "a scene").optional();
    s.output<loom::Scene>("scene", "the merged scene");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    loom::Scene merged;
    std::string camera_from, environment_from;
    for (const char* n : kInputs) {
      if (!in.has(n)) continue;
      const loom::Scene& s = in.get<loom::Scene>(n);
      merged.objects.insert(merged.objects.end(), s.objects.begin(), s.objects.end());
      merged.lights.insert(merged.lights.end(), s.lights.begin(), s.lights.end());
      if (s.camera) {
        if (!camera_from.empty())
          ctx.warn(std::string("input ") + n + "'s camera replaces input " + camera_from + "'s");
        merged.camera = s.camera;
        camera_from = n;
      }
      if (s.environment.map || !s.environment.black()) {
        if (!environment_from.empty())
          ctx.warn(std::string("input ") + n + "'s environment replaces input " + environment_from + "'s");
        merged.environment = s.environment;
        environment_from = n;
      }
    }
    out.set("scene", std::move(merged));
  }
};
LOOM_NODE(MergeScenes);

}  // namespace
