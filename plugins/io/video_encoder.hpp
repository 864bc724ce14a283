// One MP4 video stream encoded by FFmpeg (libavcodec, libavformat, libswscale)
// with every setting fixed here rather than by the machine, so the same frames
// give the same bytes whatever the cores and threads of the process.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>

namespace loom::io {

class VideoEncoder {
 public:
  enum class Codec { h264, mpeg4 };
  // True when this FFmpeg has the encoder (libx264 for H.264, its own mpeg4).
  static bool available(Codec codec);
  // Opens `file` for writing; throws loom::Error naming FFmpeg's reason.
  VideoEncoder(const std::filesystem::path& file, Codec codec, int width, int height, double fps);
  ~VideoEncoder();
  VideoEncoder(const VideoEncoder&) = delete;
  VideoEncoder& operator=(const VideoEncoder&) = delete;

  // One frame: height rows of width RGB byte triples, without padding.
  void write_rgb(const std::uint8_t* rgb);
  // Drains the encoder and writes the MP4 index; throws on any write error.
  void finish();

 private:
  struct State;
  std::unique_ptr<State> s_;
};

// The frames (packets) of the first video stream of a video file; 0 when it
// cannot be read.
int count_video_frames(const std::filesystem::path& file);

}  // namespace loom::io
