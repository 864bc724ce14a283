// Environment: light from infinitely far away, a lat-long radiance map or a
// uniform color (loom/scene.hpp fixes the lat-long convention).
#include "loom/plugin.hpp"
#include "loom/scene.hpp"
#include "transform.hpp"

namespace {

struct EnvironmentNode {
  static constexpr const char* name = "Environment";
  static void declare(loom::NodeSpec& s) {
    s.describe("A scene holding only an environment: a lat-long (equirectangular) radiance map, "
               "top row straight up, or a uniform color when no map is linked.")
        .input<loom::Image>("map", "lat-long radiance map (linear; e.g. an EXR or HDR)").optional()
        .input<loom::Color>("color", loom::Color{Eigen::Vector4d(1, 1, 1, 1)},
                            "uniform radiance when no map is linked, linear RGB")
        .input<double>("intensity", 1.0, "multiplies the map or the color")
        .range(0, 1e12)
        .input<double>("rotation_degrees", 0.0, "turns the map about +y")
        .range(-36000, 36000)
        .output<loom::Scene>("scene", "a scene holding the environment");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    loom::Environment env;
    env.color = in.get<loom::Color>("color").rgba.head<3>();
    if ((env.color.array() < 0).any()) throw loom::Error("color must be non-negative");
    env.intensity = in.get<double>("intensity");
    env.rotation = loom::scene::radians(in.get<double>("rotation_degrees"));
    if (in.has("map")) {
      auto map = in.share<loom::Image>("map");
      loom::require_finite(*map, "map");
      if (map->channels() != 1 && map->channels() < 3)
        throw loom::Error("map needs 1 (gray) or at least 3 (RGB) channels");
      if (map->width() < 2 || map->height() < 1) throw loom::Error("map is too small");
      double min_value = 0;
      cv::minMaxIdx(map->pixels.isContinuous() ? map->pixels.reshape(1) : map->pixels.clone().reshape(1),
                    &min_value);
      if (min_value < 0) throw loom::Error("map has negative values");
      if (map->encoding == loom::Encoding::srgb) {
        ctx.log("map: decoded from sRGB to linear radiance");
        map = std::make_shared<const loom::Image>(loom::with_encoding(*map, loom::Encoding::linear));
      }
      env.map = std::move(map);
    }
    loom::Scene scene;
    scene.environment = env;
    out.set("scene", std::move(scene));
  }
};
LOOM_NODE(EnvironmentNode);

}  // namespace
