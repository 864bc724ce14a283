// Reading one layer of an image file through OpenImageIO, as strictly as
// Loom read files before: 1-4 channels in a known order, 8/16-bit unsigned
// or float samples, alpha as stored; anything else is refused by name.
#include <algorithm>
#include <set>

#include <OpenImageIO/imageio.h>
#include <opencv2/core.hpp>

#include "image_files.hpp"
#include "loom/error.hpp"
#include "oiio_module.hpp"

namespace loom::io::oiio {

namespace {

std::string layer_of(const std::string& channel) {
  const auto dot = channel.rfind('.');
  return dot == std::string::npos ? std::string() : channel.substr(0, dot);
}

std::string short_name(const std::string& channel) {
  const auto dot = channel.rfind('.');
  return dot == std::string::npos ? channel : channel.substr(dot + 1);
}

// Loom's channel orders by the names a layer holds; one channel of any name
// (depth's "Z", a sample count's "X") is gray.
const std::vector<std::vector<std::string>>& known_orders() {
  static const std::vector<std::vector<std::string>> orders = {
      {"R", "G", "B", "A"}, {"R", "G", "B"}, {"Y", "A"}, {"Y"}, {"X", "Y", "Z"}};
  return orders;
}

std::string joined(const std::vector<std::string>& names) {
  std::string text;
  for (const auto& n : names) text += (text.empty() ? "" : ", ") + n;
  return text;
}

struct Part {
  int subimage = 0;
  OIIO::ImageSpec spec;
  std::string name;  // the OpenEXR part's name, if any
};

std::vector<Part> parts_of(OIIO::ImageInput& in) {
  std::vector<Part> parts;
  for (int s = 0; in.seek_subimage(s, 0); ++s) {
    Part p{s, in.spec(), {}};
    p.name = p.spec.get_string_attribute("oiio:subimagename", p.spec.get_string_attribute("name"));
    parts.push_back(std::move(p));
  }
  return parts;
}

// Every layer a file holds: part names and channel prefixes ("" unnamed).
std::vector<std::string> layer_names(const std::vector<Part>& parts) {
  std::set<std::string> names;
  for (const Part& p : parts) {
    if (parts.size() > 1 && !p.name.empty()) names.insert(p.name);
    for (const auto& c : p.spec.channelnames) names.insert(layer_of(c));
  }
  std::vector<std::string> list;
  for (const auto& n : names) list.push_back(n.empty() ? "\"\" (unnamed)" : n);
  return list;
}

struct Selection {
  const Part* part = nullptr;
  std::vector<int> indices;  // into the part's channels, in Loom's order
  std::vector<std::string> names;
};

// The channels of `layer` in one part, in Loom's order; empty when the part
// has none; throws when they are in no order Loom knows.
Selection select_in(const Part& part, const std::string& layer, bool whole_part, const std::string& what) {
  Selection s;
  s.part = &part;
  std::vector<std::pair<std::string, int>> found;
  for (int c = 0; c < part.spec.nchannels; ++c) {
    const std::string& name = part.spec.channelnames[static_cast<std::size_t>(c)];
    if (whole_part || layer_of(name) == layer) found.emplace_back(short_name(name), c);
  }
  if (found.empty()) return s;
  std::vector<std::string> held;
  for (const auto& f : found) held.push_back(f.first);
  const auto lookup = [&](const std::string& n) {
    return std::find_if(found.begin(), found.end(), [&](const auto& f) { return f.first == n; })->second;
  };
  if (found.size() == 1) {
    s.indices = {found[0].second};
    s.names = held;
    return s;
  }
  for (const auto& order : known_orders()) {
    if (order.size() != found.size()) continue;
    if (!std::all_of(order.begin(), order.end(),
                     [&](const std::string& n) { return std::find(held.begin(), held.end(), n) != held.end(); }))
      continue;
    for (const auto& n : order) s.indices.push_back(lookup(n));
    s.names = order;
    return s;
  }
  throw Error("cannot read " + what + ": its channels " + joined(held) +
              " are in no order Loom reads (gray Y, Y+A, RGB, RGBA, XYZ or one channel)");
}

Selection select(const std::vector<Part>& parts, const std::string& layer, const std::string& what) {
  const auto missing = [&] {
    return Error("cannot read " + what + ": it has no layer " +
                 (layer.empty() ? "\"\" (unnamed)" : "\"" + layer + "\"") + "; it holds " + joined(layer_names(parts)) +
                 " (name one with LoadImage's layer)");
  };
  if (parts.size() > 1) {  // a multi-part file: a part by its name, else a channel prefix within a part
    for (const Part& p : parts)
      if (!layer.empty() && p.name == layer) {
        Selection s = select_in(p, layer, false, what);
        return s.indices.empty() ? select_in(p, layer, true, what) : s;
      }
    if (layer.empty()) throw missing();
  }
  for (const Part& p : parts) {
    Selection s = select_in(p, layer, false, what);
    if (!s.indices.empty()) return s;
  }
  throw missing();
}

// The sample type Loom keeps: 8-bit, 16-bit or float (half and double widen).
OIIO::TypeDesc kept_type(const OIIO::ImageSpec& spec, const Selection& s, const std::string& what) {
  bool floating = false, eight = false, sixteen = false;
  for (int c : s.indices) {
    const OIIO::TypeDesc t = spec.channelformat(c);
    if (t == OIIO::TypeDesc::HALF || t == OIIO::TypeDesc::FLOAT || t == OIIO::TypeDesc::DOUBLE)
      floating = true;
    else if (t == OIIO::TypeDesc::UINT8)
      eight = true;
    else if (t == OIIO::TypeDesc::UINT16)
      sixteen = true;
    else
      throw Error("cannot read " + what + ": it holds " + std::string(t.c_str()) +
                  " samples (Loom reads 8- and 16-bit unsigned and float)");
  }
  if (int(floating) + int(eight) + int(sixteen) > 1)
    throw Error("cannot read " + what + ": its channels mix sample types");
  return floating ? OIIO::TypeDesc::FLOAT : eight ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::UINT16;
}

int cv_depth(OIIO::TypeDesc t) {
  return t == OIIO::TypeDesc::UINT8 ? CV_8U : t == OIIO::TypeDesc::UINT16 ? CV_16U : CV_32F;
}

}  // namespace

ImageLayer read(const std::filesystem::path& path, const std::string& layer, std::uint64_t max_pixels) {
  const std::string what = "image " + path.string();
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);  // alpha as stored: never multiplied into the colour
  auto in = OIIO::ImageInput::open(path.string(), &config);
  if (!in) throw Error("cannot decode " + what + ": " + OIIO::geterror());
  const std::vector<Part> parts = parts_of(*in);
  const Selection s = select(parts, layer, what);
  const OIIO::ImageSpec& spec = s.part->spec;
  if (spec.deep || spec.depth > 1) throw Error("cannot read " + what + ": deep and volume images are not read");
  const auto w = static_cast<std::uint64_t>(spec.width), h = static_cast<std::uint64_t>(spec.height);
  if (w == 0 || h == 0 || w > max_pixels / h)
    throw Error("cannot decode " + what + ": it holds " + std::to_string(w) + "×" + std::to_string(h) +
                " pixels, more than the limit of " + std::to_string(max_pixels) + " (LoadImage's max_pixels)");
  const OIIO::TypeDesc type = kept_type(spec, s, what);
  cv::Mat all(spec.height, spec.width, CV_MAKETYPE(cv_depth(type), spec.nchannels));
  if (!in->read_image(s.part->subimage, 0, 0, spec.nchannels, type, all.data))
    throw Error("cannot decode " + what + ": " + in->geterror());
  ImageLayer out;
  out.name = layer;
  out.channels = s.names;
  out.color_space = spec.get_string_attribute(color_space_attribute(layer));
  out.pixels.create(spec.height, spec.width, CV_MAKETYPE(cv_depth(type), static_cast<int>(s.indices.size())));
  std::vector<int> pairs;
  for (std::size_t k = 0; k < s.indices.size(); ++k) {
    pairs.push_back(s.indices[k]);
    pairs.push_back(static_cast<int>(k));
  }
  cv::mixChannels(&all, 1, &out.pixels, 1, pairs.data(), s.indices.size());
  return out;
}

}  // namespace loom::io::oiio
