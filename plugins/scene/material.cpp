// Material: how a surface scatters and emits light (loom/scene.hpp). Textures
// are linked images; color maps are used in linear values, normal maps as
// stored.
#include <string>

#include "loom/plugin.hpp"
#include "loom/scene.hpp"

namespace {

using loom::Color;
using loom::Image;

// A color map in linear values: an sRGB-tagged image is decoded once here.
std::shared_ptr<const Image> linear_map(loom::Inputs& in, const char* name, loom::Context& ctx) {
  if (!in.has(name)) return nullptr;
  auto map = in.share<Image>(name);
  loom::require_finite(*map, name);
  if (map->encoding == loom::Encoding::linear) return map;
  ctx.log(std::string(name) + ": decoded from sRGB to linear");
  return std::make_shared<const Image>(loom::with_encoding(*map, loom::Encoding::linear));
}

struct MaterialNode {
  static constexpr const char* name = "Material";
  static void declare(loom::NodeSpec& s) {
    s.describe(
         "A surface material for Render and PathTrace. The rasterizer shades every model with "
         "Blinn-Phong (base color, specular, roughness); the path tracer follows the model.")
        .enum_input("model", loom::Material::Model::diffuse,
                    {{loom::Material::Model::diffuse, "diffuse"},
                     {loom::Material::Model::plastic, "plastic"},
                     {loom::Material::Model::conductor, "conductor"},
                     {loom::Material::Model::dielectric, "dielectric"}},
                    "diffuse (Lambert), plastic (Lambert under a coat), conductor (GGX metal), "
                    "dielectric (glass)")
        .input<Color>("base_color", Color{Eigen::Vector4d(0.8, 0.8, 0.8, 1)},
                      "albedo (diffuse, plastic), reflectance at normal incidence (conductor), "
                      "tint (dielectric); linear RGB")
        .input<Image>("base_color_map", "texture multiplying base_color at the mesh's UVs")
        .optional()
        .input<Image>("normal_map",
                      "tangent-space normal map, values as stored ([0,1] encodes [-1,1]); load it "
                      "with LoadImage decode=keep")
        .optional()
        .input<Image>("displacement_map", "height along the normal (channel 0): tessellated by Render, subdivided by PathTrace")
        .optional()
        .input<double>("displacement_scale", 0.0, "displacement in scene units per unit height")
        .range(-1e6, 1e6)
        .input<double>("roughness", 0.5, "perceptual roughness; GGX alpha = roughness^2")
        .range(0, 1)
        .input<double>("specular", 0.5, "strength of the rasterizer's highlight")
        .range(0, 1)
        .input<double>("ior", 1.5, "index of refraction (plastic coat, dielectric)")
        .range(1, 4)
        .input<Color>("emission", Color{Eigen::Vector4d(0, 0, 0, 1)},
                      "emitted radiance color, linear RGB: an emissive mesh is an area light")
        .input<double>("emission_strength", 1.0, "multiplies emission")
        .range(0, 1e9)
        .output<loom::Material>("material", "the material");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    loom::Material m;
    m.model = in.get<loom::Material::Model>("model");
    m.base_color = in.get<Color>("base_color").rgba.head<3>();
    m.emission = in.get<Color>("emission").rgba.head<3>() * in.get<double>("emission_strength");
    if ((m.base_color.array() < 0).any() || (m.emission.array() < 0).any())
      throw loom::Error("base_color and emission must be non-negative");
    m.base_color_map = linear_map(in, "base_color_map", ctx);
    if (in.has("normal_map")) {
      m.normal_map = in.share<Image>("normal_map");
      loom::require_finite(*m.normal_map, "normal_map");
      if (m.normal_map->channels() < 3) throw loom::Error("normal_map needs 3 channels (x, y, z)");
    }
    if (in.has("displacement_map")) {
      m.displacement_map = in.share<Image>("displacement_map");
      loom::require_finite(*m.displacement_map, "displacement_map");
    }
    m.displacement_scale = in.get<double>("displacement_scale");
    m.roughness = in.get<double>("roughness");
    m.specular = in.get<double>("specular");
    m.ior = in.get<double>("ior");
    out.set("material", std::move(m));
  }
};
LOOM_NODE(MaterialNode);

}  // namespace
