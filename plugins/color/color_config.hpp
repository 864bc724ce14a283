// The OpenColorIO config colour names refer to: $OCIO when set (a studio's
// config), else the one Loom ships (share/ocio/loom.ocio, OCIO 2.1 built-in
// transforms only), found beside the plugin as share/loom/ocio/loom.ocio.
#pragma once

#include <string>
#include <vector>

#include <OpenColorIO/OpenColorIO.h>

#include "loom/image.hpp"

namespace loom::color {

namespace OCIO = OCIO_NAMESPACE;

// Loom's config's names for its two image encodings.
inline constexpr const char* kLinearSpace = "lin_rec709";
inline constexpr const char* kSrgbSpace = "srgb";

// Loaded once per process; throws loom::Error naming the file and OCIO's reason.
OCIO::ConstConfigRcPtr config();
// What the nodes declare: the config's colour spaces (scene- and
// display-referred, in its order), its default display's views, and the
// defaults. Never throws: nodes are declared when the plugin loads, where an
// exception would end the process. Without a config (a bad $OCIO) it holds
// Loom's two spaces and `problem` says why; the nodes then fail when they run.
struct Choices {
  std::vector<std::string> spaces;
  std::string linear_space;  // Loom's linear images (the default target)
  std::string display;
  std::vector<std::string> views;
  std::string default_view;
  std::string problem;  // empty when the config loaded
};
const Choices& choices();
// A node's `from` input: kTagged (the space the image names, or its
// encoding's: image_space) then the config's spaces.
constexpr const char* kTagged = "image";
std::vector<std::string> from_choices();
// The space a `from` input names: itself, or for kTagged the image's.
std::string source_space(const std::string& from, const Image& image, const OCIO::ConstConfigRcPtr& c);
// The space an image's values are in: the one it names, or its encoding's.
std::string image_space(const Image& image, const OCIO::ConstConfigRcPtr& c);

// What a Loom image tagged `encoding` is in the config: Loom's two encodings
// are lin_rec709 and srgb in Loom's config and the scene_linear and
// color_picking roles in a studio's.
std::string space_of(Encoding encoding, const OCIO::ConstConfigRcPtr& c);
// The encoding a converted image is tagged with: linear for scene- and
// display-linear spaces, srgb for display-encoded (sdr-video) ones; throws
// for any other (log, data) space, which a Loom image cannot be tagged with.
Encoding encoding_of(const std::string& space, const OCIO::ConstConfigRcPtr& c);

// What an image in colour space `name` carries: its encoding (encoding_of)
// and the space's name, left empty where the encoding stands for it (so one
// image has one description).
Image described_as(const std::string& name, const OCIO::ConstConfigRcPtr& c);

// The processor applied to the colour channels (alpha passes through), the
// result described as `as` is (its pixels unused); 1- and 2-channel images
// are refused.
Image apply(const OCIO::ConstProcessorRcPtr& processor, const Image& image, const Image& as);

}  // namespace loom::color
