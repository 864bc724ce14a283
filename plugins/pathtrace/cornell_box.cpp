// CornellBox: the classic scene, generated (no files).
#include "cornell_box_scene.hpp"
#include "loom/plugin.hpp"

namespace {

struct CornellBox {
  static constexpr const char* name = "CornellBox";
  static void declare(loom::NodeSpec& s) {
    s.describe("The Cornell box from Cornell's measured data (millimetres), with its camera and a "
               "one-sided area light in the ceiling; the two white blocks, or a mirror and a glass "
               "ball, or nothing inside.")
        .enum_input("contents", loom::pathtrace::CornellContents::blocks,
                    {{loom::pathtrace::CornellContents::blocks, "blocks"},
                     {loom::pathtrace::CornellContents::spheres, "spheres"},
                     {loom::pathtrace::CornellContents::empty, "empty"}},
                    "what stands in the box")
        .input<loom::Color>("light", loom::Color{{17, 12, 4, 1}},
                            "the light's emitted radiance (linear RGB)")
        .input<bool>("camera", true,
                     "include the box's camera (eye 278 273 -800, 39.3° vertical field); off: a Camera "
                     "node merged in gives it, and the viewer's orbit moves that")
        .output<loom::Scene>("scene", "walls, light, contents and camera");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    loom::pathtrace::CornellBoxOptions options;
    options.contents = in.get<loom::pathtrace::CornellContents>("contents");
    options.light_radiance = in.get<loom::Color>("light").rgba.head<3>();
    if (!options.light_radiance.allFinite() || (options.light_radiance.array() < 0).any())
      throw loom::Error("light must be a finite, non-negative color");
    loom::Scene scene = loom::pathtrace::cornell_box(options);
    if (!in.get<bool>("camera")) scene.camera.reset();
    out.set("scene", std::move(scene));
  }
};
LOOM_NODE(CornellBox);

}  // namespace
