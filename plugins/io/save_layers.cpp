// SaveLayers: several images (a renderer's image and its AOVs) as the named
// layers of one OpenEXR file, the multi-layer EXR Blender and Nuke read.
#include "image_codec.hpp"
#include "loom/plugin.hpp"
#include "provenance.hpp"

namespace {

enum class Precision { f32, f16 };

// The layers a file may hold: the input's name is the layer's, and the names
// its channels take (Blender's passes: "Normal.X", "Depth.Z").
struct LayerInput {
  const char* name;
  const char* text;
  std::vector<std::string> channels;
};

const std::vector<LayerInput>& layer_inputs() {
  static const std::vector<LayerInput> inputs = {
      {"image", "the beauty image: image.R, .G, .B (.A)", {"R", "G", "B", "A"}},
      {"albedo", "albedo.R, .G, .B", {"R", "G", "B"}},
      {"normal", "normal.X, .Y, .Z", {"X", "Y", "Z"}},
      {"depth", "depth.Z (one channel)", {"Z"}},
      {"samples", "samples.X: samples per pixel (one channel)", {"X"}},
  };
  return inputs;
}

struct SaveLayers {
  static constexpr const char* name = "SaveLayers";
  static void declare(loom::NodeSpec& s) {
    s.describe("Writes the images linked to it as the named layers of one OpenEXR file (linear float or "
               "half): channels image.R, albedo.R, normal.X, depth.Z... in one part, as Blender and Nuke "
               "read multi-layer EXR, or one part per layer. LoadImage reads a layer back by its name. Every "
               "image must have the same size; the header names the node, its seed and the frame.")
        .set_sink();
    for (const LayerInput& l : layer_inputs()) s.input<loom::Image>(l.name, l.text).optional();
    s.input<std::string>("path", "the .exr file to write, relative to the output folder; {frame:04} in it "
                                 "becomes the frame number")
        .output_file()
        .enum_input("precision", Precision::f32, {{Precision::f32, "float"}, {Precision::f16, "half"}},
                    "32-bit float or 16-bit half samples")
        .input<bool>("tiled", false, "store 64x64 tiles instead of scanlines")
        .input<bool>("parts", false, "one part per layer (multi-part EXR) instead of one part of prefixed channels");
  }
  static void run(loom::Inputs& in, loom::Outputs&, loom::Context& ctx) {
    std::vector<loom::io::NamedImage> layers;
    for (const LayerInput& l : layer_inputs())
      if (in.has(l.name)) layers.push_back({l.name, in.get<loom::Image>(l.name), l.channels});
    if (layers.empty())
      throw loom::Error("no image linked: link at least one of image, albedo, normal, depth, samples");
    const std::string& path = in.get<std::string>("path");
    loom::io::write_layers(layers, path, in.get<Precision>("precision") == Precision::f16, in.get<bool>("tiled"),
                           in.get<bool>("parts"), loom::io::provenance(ctx));
    ctx.log("wrote " + path + " (" + std::to_string(layers.size()) + " layers)");
  }
};
LOOM_NODE(SaveLayers);

}  // namespace
