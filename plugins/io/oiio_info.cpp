// What `loom info FILE` prints about an image file: its format and size, each
// part's layers and channels, and the header attributes Loom writes.
#include <map>
#include <sstream>

#include <OpenImageIO/imageio.h>

#include "loom/error.hpp"
#include "oiio_module.hpp"

namespace loom::io::oiio {

namespace {

// "albedo: R G B (half)", one line per layer of a part, in the file's order.
void print_layers(std::ostringstream& text, const OIIO::ImageSpec& spec) {
  std::vector<std::string> order;
  std::map<std::string, std::string> channels;
  for (int c = 0; c < spec.nchannels; ++c) {
    const std::string& name = spec.channelnames[static_cast<std::size_t>(c)];
    const auto dot = name.rfind('.');
    const std::string layer = dot == std::string::npos ? "" : name.substr(0, dot);
    if (!channels.count(layer)) order.push_back(layer);
    channels[layer] +=
        " " + (dot == std::string::npos ? name : name.substr(dot + 1)) + " (" + spec.channelformat(c).c_str() + ")";
  }
  for (const auto& layer : order)
    text << "  layer " << (layer.empty() ? "\"\"" : layer) << ":" << channels[layer] << "\n";
}

void print_attributes(std::ostringstream& text, const OIIO::ImageSpec& spec) {
  for (const OIIO::ParamValue& p : spec.extra_attribs) {
    const std::string name = p.name().string();
    if (name.rfind("loom:", 0) == 0 || name == "ImageDescription" || name == "Software")
      text << "  " << name << ": " << spec.metadata_val(p, true) << "\n";
  }
}

}  // namespace

std::string describe(const std::filesystem::path& path) {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path.string(), &config);
  if (!in) throw Error("cannot read " + path.string() + ": " + OIIO::geterror());
  std::ostringstream text;
  text << path.string() << ": " << in->format_name() << "\n";
  for (int s = 0; in->seek_subimage(s, 0); ++s) {
    const OIIO::ImageSpec& spec = in->spec();
    const std::string name = spec.get_string_attribute("oiio:subimagename", spec.get_string_attribute("name"));
    text << "part " << s << (name.empty() ? "" : " \"" + name + "\"") << ": " << spec.width << "x" << spec.height
         << ", " << spec.nchannels << " channels"
         << (spec.tile_width ? ", tiles " + std::to_string(spec.tile_width) + "x" + std::to_string(spec.tile_height)
                             : std::string(", scanlines"))
         << "\n";
    print_layers(text, spec);
    print_attributes(text, spec);
  }
  return text.str();
}

}  // namespace loom::io::oiio
