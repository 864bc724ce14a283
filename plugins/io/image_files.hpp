// Image files through OpenImageIO, in a library of their own
// (lib/libloom_image_files.so) that the io plugin opens at its first image
// file. libOpenImageIO as Debian 12 builds it needs 260 shared libraries
// (GDAL, OpenVDB, FFmpeg, GStreamer...): about a second of dynamic linking per
// process on the shared 2-core machine, which every `loom run` of a graph with
// an image node, and every test process linking the io plugin's codecs, would
// otherwise pay at start-up whether or not it touches a file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core/mat.hpp>

namespace loom::io {

// One image of a file: the unnamed layer ("") or a named one. Pixels in
// Loom's channel order (gray, gray+alpha, RGB, RGBA; XYZ), 8-bit, 16-bit or
// float as the file holds them. `channels` names each channel as OpenEXR does
// ("R", "G", "B", "A"; "X", "Y", "Z"; "Y" for gray); in a layered EXR a
// channel is "<layer>.<channel>" (Blender's and Nuke's convention:
// "albedo.R", "normal.X", "depth.Z").
struct ImageLayer {
  std::string name;
  cv::Mat pixels;  // CV_8U, CV_16U or CV_32F, 1-4 channels
  std::vector<std::string> channels;
  // The OpenColorIO colour space the image names, "" for its encoding's own:
  // written into the header as color_space_attribute(name), read from it.
  std::string color_space;
};

// The header attribute naming a layer's OpenColorIO colour space, written
// where the image names one ("loom:colorspace", "loom:colorspace.albedo").
inline std::string color_space_attribute(const std::string& layer) {
  return layer.empty() ? "loom:colorspace" : "loom:colorspace." + layer;
}

struct WriteOptions {
  bool half = false;   // EXR: 16-bit half floats instead of 32-bit floats
  bool tiled = false;  // EXR and TIFF: 64×64 tiles instead of scanlines
  bool parts = false;  // EXR: one part per layer (multi-part) instead of one part of prefixed channels
  std::vector<std::pair<std::string, std::string>> metadata;  // header attributes ("loom:node", ...)
  // Asked between bands of about 8 MB of scanlines; true stops the write
  // (loom::Cancelled). Tiled files are written in one call.
  std::function<bool()> cancelled;
};

// What lib/libloom_image_files.so exports as loom_image_files().
struct ImageFiles {
  int version;  // kImageFilesVersion: the plugin and the library are built together
  // The layer `layer` ("" for the unnamed channels) of a file; throws
  // loom::Error for a file that holds anything else than 1-4 channels of
  // 8/16-bit or float samples in a known order, or more than max_pixels.
  ImageLayer (*read)(const std::filesystem::path& path, const std::string& layer, std::uint64_t max_pixels);
  // Writes every layer (all of one size) into one file, by its extension.
  void (*write)(const std::vector<ImageLayer>& layers, const std::filesystem::path& path, const WriteOptions& options);
};
constexpr int kImageFilesVersion = 3;

// The library, opened on first use from beside libloom_types (lib/); throws
// loom::Error saying which file is missing or why it cannot be loaded.
const ImageFiles& image_files();

}  // namespace loom::io
