// Writing layers into one image file through OpenImageIO: pixels as given
// (quantized by the caller for 8/16-bit files), alpha unassociated as Loom
// keeps it, header attributes (provenance) in every format that has a place
// for them.
#include <algorithm>

#include <OpenImageIO/imageio.h>
#include <opencv2/core.hpp>

#include "image_files.hpp"
#include "loom/error.hpp"
#include "oiio_module.hpp"

namespace loom::io::oiio {

namespace {

OIIO::TypeDesc oiio_type(int cv_depth) {
  return cv_depth == CV_8U    ? OIIO::TypeDesc::UINT8
         : cv_depth == CV_16U ? OIIO::TypeDesc::UINT16
                              : OIIO::TypeDesc::FLOAT;
}

std::string channel_name(const std::string& layer, const std::string& channel) {
  return layer.empty() ? channel : layer + "." + channel;
}

// The header every part carries: type, tiling, compression, metadata.
OIIO::ImageSpec base_spec(const cv::Mat& pixels, int channels, const std::string& format, const WriteOptions& o) {
  OIIO::TypeDesc type = oiio_type(pixels.depth());
  if (format == "openexr") type = o.half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT;
  OIIO::ImageSpec spec(pixels.cols, pixels.rows, channels, type);
  if (o.tiled && (format == "openexr" || format == "tiff")) spec.tile_width = spec.tile_height = 64;
  if (format == "openexr" || format == "tiff") spec.attribute("compression", "zip");
  if (format == "jpeg") spec.attribute("CompressionQuality", 95);  // OpenCV's default, which Loom wrote before
  // Loom's alpha is unassociated (straight); without this OIIO divides the
  // colour by alpha when it writes a PNG or TIFF.
  spec.attribute("oiio:UnassociatedAlpha", 1);
  spec.attribute("Software", "Loom");
  // OIIO stamps an EXR with the time of writing unless told a time: none, so
  // that a file's bytes depend on what it holds, not on when it was written.
  spec.attribute("DateTime", "");
  for (const auto& [key, value] : o.metadata) spec.attribute(key, value);
  return spec;
}

// The colour space each layer names, in the header of the part holding it.
void name_color_spaces(OIIO::ImageSpec& spec, const ImageLayer* first, const ImageLayer* end) {
  for (const ImageLayer* l = first; l != end; ++l)
    if (!l->color_space.empty()) spec.attribute(color_space_attribute(l->name), l->color_space);
}

// All layers side by side in one buffer of float or the layers' own type.
cv::Mat interleaved(const std::vector<ImageLayer>& layers) {
  std::vector<cv::Mat> planes;
  for (const ImageLayer& l : layers) {
    std::vector<cv::Mat> p;
    cv::split(l.pixels, p);
    planes.insert(planes.end(), p.begin(), p.end());
  }
  cv::Mat all;
  cv::merge(planes, all);
  return all;
}

void check_layers(const std::vector<ImageLayer>& layers, const std::string& what) {
  if (layers.empty()) throw Error("cannot write " + what + ": no image");
  for (const ImageLayer& l : layers) {
    if (l.pixels.size() != layers[0].pixels.size() || l.pixels.depth() != layers[0].pixels.depth())
      throw Error("cannot write " + what + ": layer \"" + l.name + "\" is " + std::to_string(l.pixels.cols) + "x" +
                  std::to_string(l.pixels.rows) + " but \"" + layers[0].name + "\" is " +
                  std::to_string(layers[0].pixels.cols) + "x" + std::to_string(layers[0].pixels.rows) +
                  ": every layer of a file has one size");
    if (static_cast<int>(l.channels.size()) != l.pixels.channels())
      throw Error("cannot write " + what + ": layer \"" + l.name + "\" names the wrong number of channels");
  }
}

// A part's pixels: scanline files in bands of about 8 MB, `cancelled` asked
// before each (an encoder's one call on a 16384² PNG took seconds).
void write_part(OIIO::ImageOutput& out, const cv::Mat& pixels, const std::string& what, const WriteOptions& o) {
  const cv::Mat data = pixels.isContinuous() ? pixels : pixels.clone();
  const auto ask = [&] {
    if (o.cancelled && o.cancelled()) throw Cancelled();
  };
  ask();
  const OIIO::TypeDesc type = oiio_type(data.depth());
  if (out.spec().tile_width > 0) {
    if (!out.write_image(type, data.data)) throw Error("cannot write " + what + ": " + out.geterror());
    return;
  }
  const int band = std::max(1, int((std::size_t(8) << 20) / std::max<std::size_t>(1, data.step[0])));
  for (int y = 0; y < data.rows; y += band) {
    ask();
    const int end = std::min(data.rows, y + band);
    if (!out.write_scanlines(y, end, 0, type, data.ptr(y))) throw Error("cannot write " + what + ": " + out.geterror());
  }
}

}  // namespace

void write(const std::vector<ImageLayer>& layers, const std::filesystem::path& path, const WriteOptions& o) {
  const std::string what = path.string();
  check_layers(layers, what);
  auto out = OIIO::ImageOutput::create(path.string());
  if (!out) throw Error("cannot write " + what + ": " + OIIO::geterror());
  const std::string format = out->format_name();
  if (layers.size() > 1 && format != "openexr")
    throw Error("cannot write " + what + ": only OpenEXR files hold several layers");
  std::vector<OIIO::ImageSpec> specs;
  if (o.parts) {
    for (const ImageLayer& l : layers) {
      OIIO::ImageSpec spec = base_spec(l.pixels, l.pixels.channels(), format, o);
      for (int c = 0; c < l.pixels.channels(); ++c)
        spec.channelnames[static_cast<std::size_t>(c)] = channel_name(l.name, l.channels[static_cast<std::size_t>(c)]);
      spec.attribute("name", l.name);  // the OpenEXR part's name
      name_color_spaces(spec, &l, &l + 1);
      specs.push_back(std::move(spec));
    }
  } else {
    int channels = 0;
    for (const ImageLayer& l : layers) channels += l.pixels.channels();
    OIIO::ImageSpec spec = base_spec(layers[0].pixels, channels, format, o);
    std::size_t c = 0;
    for (const ImageLayer& l : layers)
      for (const auto& name : l.channels) spec.channelnames[c++] = channel_name(l.name, name);
    name_color_spaces(spec, layers.data(), layers.data() + layers.size());
    specs.push_back(std::move(spec));
  }
  if (specs.size() > 1 && !out->supports("multiimage"))
    throw Error("cannot write " + what + ": " + format + " files hold one part");
  if (!out->open(path.string(), static_cast<int>(specs.size()), specs.data()))
    throw Error("cannot write " + what + ": " + out->geterror());
  for (std::size_t k = 0; k < specs.size(); ++k) {
    if (k > 0 && !out->open(path.string(), specs[k], OIIO::ImageOutput::AppendSubimage))
      throw Error("cannot write " + what + ": " + out->geterror());
    write_part(*out, o.parts || layers.size() == 1 ? layers[k].pixels : interleaved(layers), what, o);
  }
  if (!out->close()) throw Error("cannot write " + what + ": " + out->geterror());
}

}  // namespace loom::io::oiio
