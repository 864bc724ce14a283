#include "image_codec.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>
#include <tbb/parallel_for.h>

#include "image_files.hpp"
#include "loom/error.hpp"
#include "loom/formats/image_header.hpp"
#include "loom/input_file.hpp"
#include "loom/temporary_file.hpp"

namespace loom::io {

namespace fs = std::filesystem;

namespace {

std::string extension(const fs::path& path) {
  std::string e = path.extension().string();
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

bool float_format(const std::string& ext) { return ext == ".exr" || ext == ".hdr"; }

// The header's declared size, checked before the decoder allocates anything
// (engine/formats reads PNG, JPEG, BMP, EXR, HDR, PNM and TIFF headers).
void require_pixels_within(const fs::path& path, std::uint64_t max_pixels) {
  std::ifstream in(path, std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.empty()) throw Error("cannot decode image " + path.string() + ": the file is empty");
  formats::require_declared_pixels_within(std::string_view(bytes.data(), bytes.size()), path.string(), max_pixels,
                                          "LoadImage's max_pixels");
}

// The depth a file of this extension is written at, or why it cannot be.
Depth file_depth(const std::string& ext, Depth depth, const fs::path& path) {
  if (ext != ".png" && ext != ".jpg" && ext != ".jpeg" && ext != ".exr" && ext != ".hdr" && ext != ".tif" &&
      ext != ".tiff" && ext != ".bmp")
    throw Error("cannot save " + path.string() + ": unknown extension (use .png, .jpg, .exr, .hdr, .tif or .bmp)");
  if (depth == Depth::f16 && ext != ".exr") throw Error(path.filename().string() + ": half depth needs .exr");
  if (float_format(ext) && depth != Depth::f16) return Depth::f32;
  if (!float_format(ext) && ext != ".tif" && ext != ".tiff" && depth == Depth::f32)
    throw Error(path.filename().string() + ": float depth needs .exr, .hdr or .tif");
  if ((ext == ".jpg" || ext == ".jpeg" || ext == ".bmp") && depth == Depth::u16)
    throw Error(path.filename().string() + ": 16-bit depth needs .png or .tif");
  return depth;
}

// Writes through a staging file beside `path` (its extension kept, for the
// encoder's choice), synced to the disk and renamed into place.
void write_staged(const std::vector<ImageLayer>& layers, const fs::path& path, const WriteOptions& options) {
  std::error_code ec;
  if (path.has_parent_path()) fs::create_directories(path.parent_path(), ec);
  if (ec) throw Error("cannot create folder " + path.parent_path().string() + ": " + ec.message());
  TemporaryFile staging(path, path.extension().string());
  image_files().write(layers, staging.path(), options);
  const int fd = ::open(staging.path().c_str(), O_RDONLY | O_CLOEXEC);
  const bool synced = fd >= 0 && ::fsync(fd) == 0;
  const int error = errno;
  if (fd >= 0) ::close(fd);
  if (!synced) throw Error("cannot write " + path.string() + ": " + std::strerror(error));
  staging.commit();
}

// A layer's channel names: one channel is the layer's one declared name
// (depth's "Z") or gray "Y"; two are gray and alpha; three or four take the
// declared names when there are enough ("X", "Y", "Z" for normals), else RGB(A).
std::vector<std::string> channel_names(int n, const std::vector<std::string>& declared) {
  if (n == 1) return {declared.size() == 1 ? declared[0] : "Y"};
  if (n == 2) return {"Y", "A"};
  if (static_cast<std::size_t>(n) <= declared.size()) return {declared.begin(), declared.begin() + n};
  return n == 3 ? std::vector<std::string>{"R", "G", "B"} : std::vector<std::string>{"R", "G", "B", "A"};
}

// What a file of extension `ext` and `depth` holds for these pixels: float
// files linear values, integer files sRGB-encoded ones quantized (clamped to
// [0, 1]). Radiance HDR and JPEG have no alpha; gray+alpha (2 channels) goes
// out as RGBA with the gray in all three colours, as it did through OpenCV
// (which no encoder took 2 channels from); HDR holds RGB only.
cv::Mat file_pixels(const Image& image, const std::string& ext, Depth depth) {
  const bool floating = depth == Depth::f32 || depth == Depth::f16;
  cv::Mat m = with_encoding(image, floating ? Encoding::linear : Encoding::srgb).pixels.clone();
  std::vector<cv::Mat> planes;
  cv::split(m, planes);
  const bool alpha = planes.size() == 2 || planes.size() == 4;
  if (alpha && (ext == ".hdr" || ext == ".jpg" || ext == ".jpeg")) planes.pop_back();
  else if (planes.size() == 2) planes = {planes[0], planes[0], planes[0], planes[1]};
  if (ext == ".hdr" && planes.size() == 1) planes = {planes[0], planes[0], planes[0]};
  cv::merge(planes, m);
  if (depth == Depth::u8) m.convertTo(m, CV_8U, 255.0);  // saturates to [0, 255]
  else if (depth == Depth::u16) m.convertTo(m, CV_16U, 65535.0);
  return m;
}

}  // namespace

Image read_image(const fs::path& path, Decode decode, std::uint64_t max_pixels, const std::string& layer) {
  require_input_file(path, "image");
  require_pixels_within(path, max_pixels);
  ImageLayer file = image_files().read(path, layer, max_pixels);
  cv::Mat m = std::move(file.pixels);
  const bool linear_file = m.depth() == CV_32F;
  const double scale = m.depth() == CV_8U ? 1.0 / 255.0 : m.depth() == CV_16U ? 1.0 / 65535.0 : 1.0;
  m.convertTo(m, CV_MAKETYPE(CV_32F, m.channels()), scale);
  // Float files can hold NaN and infinities (a renderer's failed samples).
  // Nodes take finite values only, so say which file, rather than let the
  // engine's output check name nothing but "image".
  if (linear_file) {
    Image image(m, Encoding::linear, file.color_space);
    require_finite(image, ("image " + path.string()).c_str());
    return image;
  }
  if (decode == Decode::linear && !file.color_space.empty())
    throw Error("cannot decode image " + path.string() + " to linear: its header names colour space " +
                file.color_space +
                ", which the sRGB curve alone does not decode (read it with decode keep, "
                "then ColorConvert it)");
  Image image(m, Encoding::srgb, file.color_space);
  return decode == Decode::linear ? with_encoding(image, Encoding::linear) : image;
}

void write_image(const Image& image, const fs::path& path, Depth depth, const Metadata& metadata, bool tiled,
                 const std::function<bool()>& cancelled) {
  if (image.empty()) throw Error("the image is empty: nothing to save");
  require_finite(image, "the image");
  const std::string ext = extension(path);
  depth = file_depth(ext, depth, path);
  // The file's pixels made in bands of rows, in parallel, `cancelled` asked
  // before each (a 16384² image's conversion took seconds in one piece).
  constexpr int kBand = 64;
  const auto band_pixels = [&](int band) {
    if (cancelled && cancelled()) throw Cancelled();
    const int first = band * kBand, end = std::min(image.height(), first + kBand);
    return file_pixels(image.like(image.pixels.rowRange(first, end)), ext, depth);
  };
  const cv::Mat top = band_pixels(0);  // its type is the file's
  cv::Mat m(image.height(), image.width(), top.type());
  top.copyTo(m.rowRange(0, top.rows));
  tbb::parallel_for(1, (image.height() + kBand - 1) / kBand, [&](int band) {
    band_pixels(band).copyTo(m.rowRange(band * kBand, std::min(image.height(), (band + 1) * kBand)));
  });
  static const std::vector<std::vector<std::string>> names = {{"Y"}, {}, {"R", "G", "B"}, {"R", "G", "B", "A"}};
  ImageLayer layer{"", m, names[static_cast<std::size_t>(m.channels() - 1)], image.space};
  WriteOptions options;
  options.half = depth == Depth::f16;
  options.tiled = tiled;
  options.metadata = metadata;
  options.cancelled = cancelled;
  write_staged({layer}, path, options);
}

void write_layers(const std::vector<NamedImage>& layers, const fs::path& path, bool half, bool tiled, bool parts,
                  const Metadata& metadata) {
  if (extension(path) != ".exr") throw Error("cannot save " + path.string() + ": layers are written to .exr files");
  std::vector<ImageLayer> files;
  for (const NamedImage& l : layers) {
    if (l.image.empty()) throw Error("layer \"" + l.name + "\" is empty: nothing to save");
    require_finite(l.image, ("layer \"" + l.name + "\"").c_str());
    const cv::Mat m = with_encoding(l.image, Encoding::linear).pixels;
    files.push_back(ImageLayer{l.name, m, channel_names(m.channels(), l.channels), l.image.space});
  }
  WriteOptions options;
  options.half = half;
  options.tiled = tiled;
  options.parts = parts;
  options.metadata = metadata;
  write_staged(files, path, options);
}

}  // namespace loom::io
