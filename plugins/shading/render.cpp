// Render: the scene through OpenGL 4.5 core on OSMesa's llvmpipe (headless):
// Blinn-Phong, normal and displacement maps, shadow maps (hard, PCF, PCSS),
// environment lighting (SH irradiance, prefiltered reflections), MSAA, points
// as sphere impostors, polylines, wireframe overlay.
#include <opencv2/imgproc.hpp>

#include "loom/image.hpp"
#include "loom/plugin.hpp"
#include "loom/scene.hpp"
#include "loom/scene_warnings.hpp"
#include "rasterizer.hpp"

namespace {

using loom::shading::ShadowFilter;

struct Render {
  static constexpr const char* name = "Render";
  static void declare(loom::NodeSpec& s) {
    s.describe("Rasterizes a scene with OpenGL 4.5 (OSMesa llvmpipe, no display or GPU needed): "
               "Blinn-Phong with the material's maps, normal mapping, displacement mapping by "
               "tessellation, shadow maps (constant + slope bias, PCF, PCSS), MSAA; point sets as "
               "shaded spheres, polylines as lines. A lat-long environment map lights the scene "
               "(diffuse by 9 SH irradiance coefficients, glossy reflection on plastic and conductor "
               "materials) and shows behind it. Linear HDR output.")
        .input<loom::Scene>("scene", "what to draw (its camera, or one framing the scene)")
        .input<int>("width", 960, "image width in pixels").range(1, 16384)
        .input<int>("height", 540, "image height in pixels").range(1, 16384)
        .input<int>("samples", 4, "MSAA samples per pixel (1: none)").range(1, 16)
        .enum_input("shadows", ShadowFilter::pcf,
                    {{ShadowFilter::off, "off"},
                     {ShadowFilter::hard, "hard"},
                     {ShadowFilter::pcf, "pcf"},
                     {ShadowFilter::pcss, "pcss"}},
                    "shadow maps: none, one comparison, k x k PCF, or PCSS soft shadows")
        .input<int>("shadow_resolution", 2048, "texels per side of each light's shadow map").range(16, 16384)
        .input<double>("shadow_bias", 1.0, "constant depth bias, in shadow-map texels").range(0, 1000)
        .input<double>("shadow_slope_bias", 1.0, "slope-scaled bias: times tan(angle to the light), in texels")
        .range(0, 1000)
        .input<int>("pcf_size", 5, "PCF kernel width k (k x k texels)").range(1, 15)
        .input<double>("light_size", 0.1,
                       "PCSS: emitter radius of point/spot lights (scene units); tangent of the "
                       "angular radius for directional lights")
        .range(0, 1000)
        .input<int>("tessellation", 16, "displacement mapping: subdivisions of each triangle edge; 0 off")
        .range(0, 64)
        .input<double>("point_radius", 0.02, "radius of points that carry none").at_least(0)
        .input<double>("line_width", 1.0, "width of polylines and wireframe, pixels").range(0.5, 64)
        .input<bool>("wireframe", false, "draw mesh edges over the shading")
        .input<loom::Color>("wireframe_color", loom::Color{}, "edge color (linear)")
        .input<bool>("alpha", false, "output RGBA with coverage in alpha, else RGB")
        .input<bool>("extra_images", true, "also render depth, normal and shadow images (else 1x1)")
        .output<loom::Image>("image", "linear radiance (tagged linear; SaveImage encodes)")
        .output<loom::Image>("depth", "distance along the view axis; the far plane on the background")
        .output<loom::Image>("normal", "world-space unit normals, 0 on the background")
        .output<loom::Image>("shadow", "visibility of the first shadowed light, 1 lit, 0 shadowed");
  }

  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    const loom::Scene& scene = in.get<loom::Scene>("scene");
    loom::shading::RenderOptions o;
    o.width = in.get<int>("width");
    o.height = in.get<int>("height");
    o.samples = in.get<int>("samples");
    o.shadows = in.get<ShadowFilter>("shadows");
    o.shadow_resolution = in.get<int>("shadow_resolution");
    o.shadow_bias = in.get<double>("shadow_bias");
    o.shadow_slope_bias = in.get<double>("shadow_slope_bias");
    o.pcf_size = in.get<int>("pcf_size");
    o.light_size = in.get<double>("light_size");
    o.tessellation = in.get<int>("tessellation");
    o.point_radius = in.get<double>("point_radius");
    o.line_width = in.get<double>("line_width");
    o.wireframe = in.get<bool>("wireframe");
    o.wireframe_color = in.get<loom::Color>("wireframe_color").rgba.head<3>();
    o.aux = in.get<bool>("extra_images");
    o.check_cancelled = [&ctx] { ctx.check_cancelled(); };
    for (const std::string& w : loom::scene_warnings(scene)) ctx.warn(w);
    using loom::shading::max_lights, loom::shading::max_shadows;
    if (scene.lights.size() > static_cast<std::size_t>(max_lights))
      ctx.warn("only the first " + std::to_string(max_lights) + " lights are drawn");
    if (o.shadows != ShadowFilter::off) {
      int shadowed = 0;
      for (const auto& l : scene.lights) shadowed += l.casts_shadow;
      if (shadowed > max_shadows)
        ctx.warn("only the first " + std::to_string(max_shadows) + " shadow-casting lights cast shadows");
    }

    // The context and compiled programs survive between evaluations.
    const auto rasterizer = ctx.scratch<loom::shading::Rasterizer>(
        loom::hash_string("shading.Rasterizer"), [] { return std::make_shared<loom::shading::Rasterizer>(); });
    if (o.samples > rasterizer->max_samples())
      ctx.warn("MSAA limited to " + std::to_string(rasterizer->max_samples()) + " samples by " +
               rasterizer->renderer());
    ctx.progress(0, 1, "rendering");
    loom::shading::RenderImages r = rasterizer->render(scene, o);
    cv::Mat image;
    if (in.get<bool>("alpha"))
      image = r.color;
    else
      cv::cvtColor(r.color, image, cv::COLOR_RGBA2RGB);
    out.set("image", loom::Image(image, loom::Encoding::linear));
    if (o.aux) {
      cv::Mat depth;
      cv::extractChannel(r.position, depth, 3);
      out.set("depth", loom::Image(depth, loom::Encoding::linear));
      out.set("normal", loom::Image(r.normal, loom::Encoding::linear));
      out.set("shadow", loom::Image(r.shadow, loom::Encoding::linear));
    } else {
      const loom::Image none(cv::Mat::zeros(1, 1, CV_32FC1), loom::Encoding::linear);
      out.set("depth", none);
      out.set("normal", none);
      out.set("shadow", none);
    }
  }
};
LOOM_NODE(Render);

}  // namespace
