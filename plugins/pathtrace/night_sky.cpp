// NightSky: a lat-long environment map made in the graph (night_sky_map.hpp).
#include "loom/plugin.hpp"
#include "night_sky_map.hpp"

namespace {

struct NightSky {
  static constexpr const char* name = "NightSky";
  static void declare(loom::NodeSpec& s) {
    s.describe("A procedural night sky as a linear lat-long radiance map: blue gradient, dim "
               "ground, stars and a bright moon disk (for environment lighting without files).")
        .input<loom::Vec2i>("size", loom::Vec2i(512, 256), "map width and height").range(2, 16384)
        .input<double>("moon_elevation_degrees", 30.0, "moon above the horizon").range(-90, 90)
        .input<double>("moon_azimuth_degrees", 35.0, "moon about +y; 0 is straight down -z").range(-360, 360)
        .input<double>("moon_radius_degrees", 1.5, "angular radius of the moon disk").range(0.01, 45)
        .input<double>("moon_radiance", 300.0, "radiance of the moon disk").at_least(0)
        .input<double>("sky_radiance", 0.03, "brightness of the sky gradient").at_least(0)
        .input<int>("stars", 400, "number of stars").range(0, 1000000)
        .output<loom::Image>("image", "linear RGB lat-long map");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    constexpr double deg = 3.14159265358979323846 / 180;
    loom::pathtrace::NightSkyOptions o;
    o.width = in.get<loom::Vec2i>("size").x();
    o.height = in.get<loom::Vec2i>("size").y();
    o.moon_elevation = in.get<double>("moon_elevation_degrees") * deg;
    o.moon_azimuth = in.get<double>("moon_azimuth_degrees") * deg;
    o.moon_radius = in.get<double>("moon_radius_degrees") * deg;
    o.moon_radiance = in.get<double>("moon_radiance");
    o.sky_radiance = in.get<double>("sky_radiance");
    o.stars = in.get<int>("stars");
    o.seed = ctx.seed();
    out.set("image", loom::pathtrace::night_sky_map(o));
  }
};
LOOM_NODE(NightSky);

}  // namespace
