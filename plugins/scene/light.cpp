// Light: a point, spot or directional light as a one-light scene. Area lights
// are emissive meshes (Material emission), not this node.
#include "loom/plugin.hpp"
#include "loom/scene.hpp"
#include "transform.hpp"

namespace {

struct LightNode {
  static constexpr const char* name = "Light";
  static void declare(loom::NodeSpec& s) {
    s.describe("A one-light scene: a point, spot or directional light. For area lights give a "
               "mesh an emissive Material.")
        .enum_input("kind", loom::Light::Kind::point,
                    {{loom::Light::Kind::point, "point"},
                     {loom::Light::Kind::spot, "spot"},
                     {loom::Light::Kind::directional, "directional"}},
                    "the kind of light")
        .input<loom::Vec3>("position", loom::Vec3(0, 5, 0), "point and spot: where the light is")
        .input<loom::Vec3>("direction", loom::Vec3(0, -1, 0),
                           "spot and directional: where the light shines")
        .input<loom::Color>("color", loom::Color{Eigen::Vector4d(1, 1, 1, 1)}, "linear RGB")
        .input<double>("intensity", 10.0,
                       "point and spot: radiant intensity (irradiance I/d^2 at distance d); "
                       "directional: irradiance")
        .range(0, 1e12)
        .input<double>("spot_inner_degrees", 20.0, "spot: half-angle of full intensity")
        .range(0, 90)
        .input<double>("spot_outer_degrees", 30.0, "spot: half-angle where intensity reaches zero")
        .range(0, 90)
        .input<bool>("casts_shadow", true, "whether this light casts shadows")
        .output<loom::Scene>("scene", "a scene holding this one light");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    loom::Light l;
    l.kind = in.get<loom::Light::Kind>("kind");
    l.position = in.get<loom::Vec3>("position");
    if (!l.position.allFinite()) throw loom::Error("position must be finite");
    if (l.kind != loom::Light::Kind::point)
      l.direction = loom::scene::unit(in.get<loom::Vec3>("direction"), "direction");
    l.color = in.get<loom::Color>("color").rgba.head<3>();
    if ((l.color.array() < 0).any()) throw loom::Error("color must be non-negative");
    l.intensity = in.get<double>("intensity");
    l.spot_inner = loom::scene::radians(in.get<double>("spot_inner_degrees"));
    l.spot_outer = loom::scene::radians(in.get<double>("spot_outer_degrees"));
    if (l.spot_inner > l.spot_outer)
      throw loom::Error("spot_inner_degrees must not exceed spot_outer_degrees");
    l.casts_shadow = in.get<bool>("casts_shadow");
    loom::Scene scene;
    scene.lights.push_back(l);
    out.set("scene", std::move(scene));
  }
};
LOOM_NODE(LightNode);

}  // namespace
