#include "image_codec.hpp"

#include <cstdlib>
#include <string>
#include <fstream>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "loom/formats/image_header.hpp"
#include "loom/input_file.hpp"
#include "loom/atomic_file.hpp"

namespace loom::io {

namespace {

// OpenCV reads OpenEXR only when asked to, through this variable, which it
// reads on first use: set it when the plugin loads, before any decoding.
const bool kExrEnabled = ::setenv("OPENCV_IO_ENABLE_OPENEXR", "1", 0) == 0;

std::string extension(const std::filesystem::path& path) {
  std::string e = path.extension().string();
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

bool float_format(const std::string& ext) { return ext == ".exr" || ext == ".hdr"; }

// OpenCV's channel order is BGR(A); Loom's is RGB(A).
void swap_red_blue(cv::Mat& m) {
  if (m.channels() == 3) cv::cvtColor(m, m, cv::COLOR_BGR2RGB);
  else if (m.channels() == 4) cv::cvtColor(m, m, cv::COLOR_BGRA2RGBA);
}

}  // namespace

Image read_image(const std::filesystem::path& path, Decode decode, std::uint64_t max_pixels) {
  (void)kExrEnabled;
  require_input_file(path, "image");
  std::ifstream in(path, std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.empty()) throw Error("cannot decode image " + path.string() + ": the file is empty");
  formats::require_declared_pixels_within(std::string_view(bytes.data(), bytes.size()), path.string(), max_pixels,
                                          "LoadImage's max_pixels");
  cv::Mat m;
  try {
    m = cv::imdecode(bytes, cv::IMREAD_UNCHANGED | cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
  } catch (const cv::Exception& e) {
    throw Error("cannot decode image " + path.string() + ": " + e.what());
  }
  if (m.empty()) throw Error("cannot decode image " + path.string() + ": not a format OpenCV reads");
  double scale = 1.0;
  const bool linear_file = m.depth() == CV_32F || m.depth() == CV_64F;
  if (m.depth() == CV_8U) scale = 1.0 / 255.0;
  else if (m.depth() == CV_16U) scale = 1.0 / 65535.0;
  m.convertTo(m, CV_MAKETYPE(CV_32F, m.channels()), scale);
  swap_red_blue(m);
  // Float files can hold NaN and infinities (a renderer's failed samples).
  // Nodes take finite values only, so say which file, rather than let the
  // engine's output check name nothing but "image".
  if (linear_file) {
    Image image(m, Encoding::linear);
    require_finite(image, ("image " + path.string()).c_str());
    return image;
  }
  Image image(m, Encoding::srgb);
  return decode == Decode::linear ? with_encoding(image, Encoding::linear) : image;
}

void write_image(const Image& image, const std::filesystem::path& path, Depth depth) {
  if (image.empty()) throw Error("the image is empty: nothing to save");
  require_finite(image, "the image");
  const std::string ext = extension(path);
  if (ext != ".png" && ext != ".jpg" && ext != ".jpeg" && ext != ".exr" && ext != ".hdr" &&
      ext != ".tif" && ext != ".tiff" && ext != ".bmp")
    throw Error("cannot save " + path.string() +
                ": unknown extension (use .png, .jpg, .exr, .hdr, .tif or .bmp)");
  if (float_format(ext) && depth != Depth::f32) depth = Depth::f32;
  if (!float_format(ext) && ext != ".tif" && ext != ".tiff" && depth == Depth::f32)
    throw Error(path.filename().string() + ": float depth needs .exr, .hdr or .tif");
  if ((ext == ".jpg" || ext == ".jpeg" || ext == ".bmp") && depth == Depth::u16)
    throw Error(path.filename().string() + ": 16-bit depth needs .png or .tif");

  // Float files hold linear values; integer files hold sRGB-encoded ones.
  const Encoding wanted = depth == Depth::f32 ? Encoding::linear : Encoding::srgb;
  cv::Mat m = with_encoding(image, wanted).pixels.clone();
  std::vector<cv::Mat> planes;
  cv::split(m, planes);
  // Radiance HDR and JPEG have no alpha; no encoder takes gray+alpha (2
  // channels), so it goes out as RGBA with the gray in all three colours.
  const bool alpha = planes.size() == 2 || planes.size() == 4;
  if (alpha && (ext == ".hdr" || ext == ".jpg" || ext == ".jpeg")) planes.pop_back();
  else if (planes.size() == 2) planes = {planes[0], planes[0], planes[0], planes[1]};
  cv::merge(planes, m);
  swap_red_blue(m);
  if (depth == Depth::u8) m.convertTo(m, CV_8U, 255.0);  // saturates to [0, 255]
  else if (depth == Depth::u16) m.convertTo(m, CV_16U, 65535.0);
  std::vector<unsigned char> bytes;
  try {
    if (!cv::imencode(ext, m, bytes)) throw Error("OpenCV cannot encode " + ext);
  } catch (const cv::Exception& e) {
    throw Error("cannot encode " + path.string() + ": " + e.what());
  }
  write_file_atomic(path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace loom::io
