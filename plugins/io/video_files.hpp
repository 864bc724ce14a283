// MP4 files through FFmpeg, in a library of their own
// (lib/libloom_video_files.so) that the io plugin opens at its first video.
// libavformat as Debian 12 builds it needs about 130 shared libraries: 0.1 s of
// processor time that every process loading the io plugin (every `loom run` of
// a graph with an image node, every farm task on Slurm) would otherwise pay
// at start-up, whether or not it writes a video. (image_files.hpp: the same
// for OpenImageIO.)
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>

namespace loom::io {

// One MP4 video stream being written (video_encoder.cpp: FFmpeg's contexts,
// every setting fixed so the same frames give the same bytes on any machine).
class VideoEncoder {
 public:
  enum class Codec { h264, mpeg4 };
  virtual ~VideoEncoder() = default;
  // One frame: height rows of width RGB byte triples, without padding.
  virtual void write_rgb(const std::uint8_t* rgb) = 0;
  // Drains the encoder and writes the MP4 index; throws on any write error.
  virtual void finish() = 0;
};

// What lib/libloom_video_files.so exports as loom_video_files().
struct VideoFiles {
  int version;  // kVideoFilesVersion: the plugin and the library are built together
  // True when this FFmpeg has the encoder (libx264 for H.264, its own mpeg4).
  bool (*available)(VideoEncoder::Codec codec);
  // Opens `file` for writing; throws loom::Error naming FFmpeg's reason.
  std::unique_ptr<VideoEncoder> (*open)(const std::filesystem::path& file, VideoEncoder::Codec codec, int width,
                                        int height, double fps);
  // The frames (packets) of the first video stream of a file; 0 when it cannot be read.
  int (*count_frames)(const std::filesystem::path& file);
};
constexpr int kVideoFilesVersion = 1;

// The library, opened on first use from beside libloom_types (lib/); throws
// loom::Error saying which file is missing or why it cannot be loaded.
const VideoFiles& video_files();

}  // namespace loom::io
