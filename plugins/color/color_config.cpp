#include "color_config.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>

#include "loom/error.hpp"

namespace loom::color {
namespace {

// The shipped config: lib/loom/plugins/libloom_color.so → share/loom/ocio/
// (the build tree and an installation have the same layout).
std::filesystem::path shipped_config() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&shipped_config), &info) == 0 || !info.dli_fname)
    throw Error("cannot find the color plugin's own file to locate share/loom/ocio/loom.ocio");
  return std::filesystem::path(info.dli_fname).parent_path() / "../../../share/loom/ocio/loom.ocio";
}

OCIO::ConstConfigRcPtr load() {
  const char* studio = std::getenv("OCIO");
  const std::filesystem::path file = studio && *studio ? std::filesystem::path(studio) : shipped_config();
  try {
    OCIO::ConstConfigRcPtr c = OCIO::Config::CreateFromFile(file.c_str());
    c->validate();
    return c;
  } catch (const OCIO::Exception& e) {
    throw Error("OpenColorIO config " + file.lexically_normal().string() + (studio && *studio ? " ($OCIO)" : "") +
                ": " + e.what());
  }
}

}  // namespace

OCIO::ConstConfigRcPtr config() {
  static std::once_flag once;
  static OCIO::ConstConfigRcPtr c;
  static std::string error;
  std::call_once(once, [] {
    try {
      c = load();
    } catch (const Error& e) {
      error = e.what();
    }
  });
  if (!c) throw Error(error);
  return c;
}

namespace {

Choices read_choices(const OCIO::ConstConfigRcPtr& c) {
  Choices out;
  const int n = c->getNumColorSpaces(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ACTIVE);
  for (int i = 0; i < n; ++i)
    out.spaces.emplace_back(c->getColorSpaceNameByIndex(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ACTIVE, i));
  out.linear_space = space_of(Encoding::linear, c);
  out.display = c->getDefaultDisplay();
  for (int i = 0; i < c->getNumViews(out.display.c_str()); ++i) out.views.emplace_back(c->getView(out.display.c_str(), i));
  out.default_view = c->getDefaultView(out.display.c_str());
  return out;
}

}  // namespace

const Choices& choices() {
  static const Choices c = [] {
    try {
      return read_choices(config());
    } catch (const std::exception& e) {
      return Choices{{kLinearSpace, kSrgbSpace}, kLinearSpace, "sRGB", {"Standard"}, "Standard", e.what()};
    }
  }();
  return c;
}

std::vector<std::string> from_choices() {
  std::vector<std::string> names = choices().spaces;
  names.insert(names.begin(), kTagged);
  return names;
}

std::string source_space(const std::string& from, const Image& image, const OCIO::ConstConfigRcPtr& c) {
  return from == kTagged ? image_space(image, c) : from;
}

std::string image_space(const Image& image, const OCIO::ConstConfigRcPtr& c) {
  return image.space.empty() ? space_of(image.encoding, c) : image.space;
}

std::string space_of(Encoding encoding, const OCIO::ConstConfigRcPtr& c) {
  const char* role = encoding == Encoding::srgb ? OCIO::ROLE_COLOR_PICKING : OCIO::ROLE_SCENE_LINEAR;
  const OCIO::ConstColorSpaceRcPtr space = c->getColorSpace(role);
  if (!space)
    throw Error(std::string("the OpenColorIO config has no role ") + role + " for Loom's " +
                (encoding == Encoding::srgb ? "sRGB-encoded" : "linear") + " images");
  return space->getName();
}

Encoding encoding_of(const std::string& name, const OCIO::ConstConfigRcPtr& c) {
  const OCIO::ConstColorSpaceRcPtr space = c->getColorSpace(name.c_str());
  if (!space) throw Error("no colour space \"" + name + "\" in the OpenColorIO config");
  const std::string encoding = space->getEncoding();
  if (!space->isData() && (encoding == "scene-linear" || encoding == "display-linear")) return Encoding::linear;
  if (!space->isData() && encoding == "sdr-video") return Encoding::srgb;
  throw Error("colour space \"" + name + "\" (" + (space->isData() ? "data" : "encoding '" + encoding + "'") +
              ") is neither linear nor display-encoded, the two kinds a Loom image is tagged with");
}

Image described_as(const std::string& name, const OCIO::ConstConfigRcPtr& c) {
  const Encoding tag = encoding_of(name, c);
  const std::string canonical = c->getColorSpace(name.c_str())->getName();  // a role or alias resolved
  return Image(cv::Mat(), tag, canonical == space_of(tag, c) ? std::string() : canonical);
}

Image apply(const OCIO::ConstProcessorRcPtr& processor, const Image& image, const Image& as) {
  if (image.channels() < 3)
    throw Error("ColorConvert needs an RGB or RGBA image, not " + std::to_string(image.channels()) + " channel(s)");
  Image out = as.like(image.pixels.clone());
  OCIO::PackedImageDesc desc(out.pixels.ptr<float>(), out.width(), out.height(), out.channels(), OCIO::BIT_DEPTH_F32,
                             sizeof(float), sizeof(float) * out.channels(),
                             static_cast<std::ptrdiff_t>(out.pixels.step[0]));
  processor->getDefaultCPUProcessor()->apply(desc);
  return out;
}

}  // namespace loom::color
