// PathTrace: the scene rendered by unidirectional path tracing with
// next-event estimation and MIS (integrator.hpp) over an Embree BVH kept in
// the node's scratch (embree_scene.hpp).
#include <chrono>

#include "embree_scene.hpp"
#include "integrator.hpp"
#include "loom/partial_pacing.hpp"
#include "loom/plugin.hpp"
#include "loom/scene_warnings.hpp"

namespace {

using namespace loom::pathtrace;

void warn_about_unused(const loom::Scene& scene, const EmbreeScene& traced, const RenderSettings& s,
                       int displacement_level, loom::Context& ctx) {
  if (traced.skipped_polylines() > 0)
    ctx.warn(std::to_string(traced.skipped_polylines()) +
             " polyline objects are not path traced (Render draws them)");
  for (const std::string& w : loom::scene_warnings(scene)) ctx.warn(w);
  bool emissive_points = false;
  for (const auto& o : scene.objects) {
    emissive_points |= o.points && (o.material.emission.array() > 0).any();
    if (o.mesh && o.mesh->has_uv() && o.material.displacement_map && o.material.displacement_scale != 0 &&
        displacement_level == 0)
      ctx.warn("object '" + o.name + "': its displacement map is ignored with displacement_subdivision 0");
  }
  if (emissive_points && s.strategy != Strategy::bsdf)
    ctx.warn("emissive points are found only by BSDF sampling (no light sampling on spheres)");
  if (!scene.lights.empty() && s.strategy == Strategy::bsdf)
    ctx.warn("point, spot and directional lights cannot be hit by BSDF sampling: with strategy "
             "'bsdf' they contribute nothing");
}

struct PathTrace {
  static constexpr const char* name = "PathTrace";
  static void declare(loom::NodeSpec& s) {
    s.describe("Path tracing (Embree 3 BVH) with next-event estimation on emissive triangles and "
               "lights, BSDF sampling and MIS (power heuristic), environment-map importance "
               "sampling (alias table, eq. 64), Russian roulette and adaptive sampling; normal maps "
               "(Render's tangent-space convention) and displacement maps (subdivided and displaced "
               "before the BVH build); linear HDR image plus albedo, normal and depth AOVs. A light "
               "with casts_shadow off lights through everything (no shadow ray); emissive meshes "
               "always cast shadows, and an object with casts_shadow off blocks no light.")
        .input<loom::Scene>("scene", "what to render; without a camera the scene is framed")
        .input<loom::Vec2i>("size", loom::Vec2i(512, 512), "image width and height").range(1, 16384)
        .input<int>("spp", 64, "samples per pixel (the most, with adaptive sampling)").range(1, 1 << 20)
        .input<int>("max_depth", 8, "bounces at most; 1 is direct light only").range(1, 1024)
        .input<bool>("russian_roulette", true, "end paths at random after rr_min_depth bounces (unbiased)")
        .input<int>("rr_min_depth", 3, "bounces before Russian roulette may end a path").range(1, 1024)
        .enum_input("strategy", Strategy::mis,
                    {{Strategy::mis, "mis"}, {Strategy::nee, "nee"}, {Strategy::bsdf, "bsdf"}},
                    "mis: light and BSDF sampling weighted by the power heuristic; nee: light "
                    "sampling only (BSDF rays ignore emitters they hit); bsdf: no light sampling")
        .enum_input("sampler", SamplerKind::sobol,
                    {{SamplerKind::sobol, "sobol"}, {SamplerKind::independent, "independent"}},
                    "sobol: Owen-scrambled Sobol points per pixel (Burley 2020), lower error per "
                    "sample; independent: a splitmix64 stream per sample")
        .enum_input("environment_sampling", EnvironmentLight::Sampling::importance,
                    {{EnvironmentLight::Sampling::importance, "importance"},
                     {EnvironmentLight::Sampling::uniform, "uniform"}},
                    "how light sampling draws directions of an environment map")
        .input<double>("adaptive_threshold", 0.0,
                       "stop a pixel when its relative standard error falls below this (0: off)")
        .range(0, 1)
        .input<int>("adaptive_min_spp", 16, "samples before a pixel may stop").range(2, 1 << 20)
        .input<int>("displacement_subdivision", 0,
                    "displacement maps: subdivide displaced meshes this many times (4 triangles "
                    "each) and move their vertices along the normals before the BVH build (0: "
                    "displacement off)")
        .range(0, 8)
        .output<loom::Image>("image", "linear HDR radiance (RGB)")
        .output<loom::Image>("albedo", "first-hit base color (RGB), for denoisers")
        .output<loom::Image>("normal", "first-hit world-space shading normal (RGB = xyz)")
        .output<loom::Image>("depth", "first-hit distance along the camera ray (0: nothing hit)")
        .output<loom::Image>("samples", "samples taken per pixel")
        .output<double>("spp", "mean samples per pixel actually taken")
        .output<loom::json>("stats", "paths, rays, seconds, throughput, estimated relative error of the mean, BVH "
                                     "build time and reuse")
        .set_pixel_independent(&summarize)
        .set_sample_passes()
        .set_version(2);  // 2: stats has relative_error
  }

  // After the engine gathers an image split over processes: the mean spp and
  // the paths counted over every pixel (rays and seconds stay the first part's).
  static void summarize(loom::Outputs& out) {
    const cv::Mat& samples = out.value("samples").as<loom::Image>().pixels;
    double sum = 0;
    for (int y = 0; y < samples.rows; ++y)
      for (int x = 0; x < samples.cols; ++x) sum += samples.at<float>(y, x);
    const double mean_spp = sum / (double(samples.rows) * samples.cols);
    loom::json stats = out.value("stats").as<loom::json>();
    stats["mean_spp"] = mean_spp;
    stats["paths"] = std::uint64_t(sum);
    out.set("spp", mean_spp);
    out.set("stats", stats);
  }

  // Progress, cancellation before every sample, and for whoever watches
  // (Context::publish_partial) the image after each pass and, inside a long
  // pass, between batches of tiles as `pacing` says (a batch lands a few ms
  // after the mark). The samples and their order per pixel are the same, so
  // the final image does not change.
  static RenderHooks hooks(loom::Context& ctx, const RenderSettings& s, loom::PartialPacing& pacing) {
    RenderHooks h;
    h.progress = [&ctx](double fraction) { ctx.progress(fraction, 1, "path tracing"); };
    h.check_cancelled = [&ctx] { ctx.check_cancelled(); };
    const auto publish = [&ctx, &pacing, spp = s.spp](const Film& film, double taken) {
      pacing.published();
      ctx.publish_partial("image", [&] { return loom::Image(mean_image(film), loom::Encoding::linear); },
                          {taken, double(spp), "spp", relative_error(film)});
    };
    h.after_pass = [&ctx, publish](const Film& film, double taken) {
      if (ctx.partial_wanted()) publish(film, taken);
    };
    h.between_batches = [&ctx, &pacing, publish](const Film& film) {
      if (ctx.partial_wanted() && pacing.due()) publish(film, mean_samples(film));
    };
    return h;
  }

  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    const auto scene = in.share<loom::Scene>("scene");
    loom::require_valid(*scene, "scene");
    if (scene->environment.map) loom::require_finite(*scene->environment.map, "scene environment map");
    for (const auto& o : scene->objects) {
      if (o.material.base_color_map)
        loom::require_finite(*o.material.base_color_map, ("base color map of " + o.name).c_str());
      if (o.material.normal_map)
        loom::require_finite(*o.material.normal_map, ("normal map of " + o.name).c_str());
      if (o.material.displacement_map)
        loom::require_finite(*o.material.displacement_map, ("displacement map of " + o.name).c_str());
    }
    const int displacement_level = in.get<int>("displacement_subdivision");
    RenderSettings s;
    const loom::Vec2i size = in.get<loom::Vec2i>("size");
    s.width = size.x();
    s.height = size.y();
    s.spp = in.get<int>("spp");
    s.max_depth = in.get<int>("max_depth");
    s.russian_roulette = in.get<bool>("russian_roulette");
    s.rr_min_depth = in.get<int>("rr_min_depth");
    s.strategy = in.get<Strategy>("strategy");
    s.sampler = in.get<SamplerKind>("sampler");
    s.environment_sampling = in.get<EnvironmentLight::Sampling>("environment_sampling");
    s.adaptive_threshold = in.get<double>("adaptive_threshold");
    s.adaptive_min_spp = in.get<int>("adaptive_min_spp");
    s.seed = ctx.seed();
    s.region = ctx.region();
    // Split by samples, every part must sum its passes at the same points
    // (Context::sum_over_parts): the pass split must not depend on who
    // watches one part (`--preview` on rank 0 only), so no passes there.
    s.progressive = ctx.partial_wanted() && !s.region.by_samples;
    if (s.region.by_samples)
      s.sum_over_parts = [&ctx](double* values, std::size_t count, double samples) {
        ctx.sum_over_parts(values, count, samples);
      };
    if (s.region.dealt()) s.take_slot = [&ctx] { return ctx.take_slot(); };

    bool built = false;
    const auto traced = ctx.scratch<EmbreeScene>(geometry_key(*scene, displacement_level), [&] {
      ctx.progress(0, 1, "building the BVH");
      built = true;
      return std::make_shared<EmbreeScene>(*scene, displacement_level, [&ctx] { return ctx.cancelled(); });
    });
    warn_about_unused(*scene, *traced, s, displacement_level, ctx);
    const loom::Camera camera =
        scene->camera ? *scene->camera : loom::framing_camera(*scene, double(s.width) / s.height);

    const auto start = std::chrono::steady_clock::now();
    loom::PartialPacing pacing;
    const RenderResult r = render(*scene, camera, *traced, s, hooks(ctx, s, pacing));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (r.nonfinite > 0)
      ctx.warn(std::to_string(r.nonfinite) + " samples were NaN or infinite and counted as black");

    out.set("image", loom::Image(r.image, loom::Encoding::linear));
    out.set("albedo", loom::Image(r.albedo, loom::Encoding::linear));
    out.set("normal", loom::Image(r.normal, loom::Encoding::linear));
    out.set("depth", loom::Image(r.depth, loom::Encoding::linear));
    out.set("samples", loom::Image(r.samples, loom::Encoding::linear));
    out.set("spp", r.mean_spp);
    out.set("stats", loom::json{{"paths", r.paths},
                                {"rays", r.rays},
                                {"seconds", seconds},
                                {"paths_per_second", double(r.paths) / std::max(seconds, 1e-9)},
                                {"rays_per_second", double(r.rays) / std::max(seconds, 1e-9)},
                                {"mean_spp", r.mean_spp},
                                {"relative_error", r.relative_error},
                                {"nonfinite_samples", r.nonfinite},
                                {"emissive_triangles", r.emissive_triangles},
                                {"environment_sampled", r.environment_sampled},
                                {"triangles", traced->triangles()},
                                {"bvh_build_seconds", traced->build_seconds()},
                                {"bvh_reused", !built}});
    ctx.progress(1, 1, "path tracing");
  }
};
LOOM_NODE(PathTrace);

}  // namespace
