// Video files from a sequence of loom::Images, written with FFmpeg's
// libavcodec and libavformat directly (one encoder thread, fixed options), so
// the bytes of an MP4 do not depend on the cores a process sees. Frames
// arrive in order; the file appears only when finished.
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "loom/image.hpp"
#include "loom/temporary_file.hpp"

namespace loom::io {

enum class VideoCodec { automatic, h264, mpeg4 };

class VideoEncoder;  // video_files.hpp: FFmpeg, from a library of its own

// Writes to a staging file beside `path` (loom/temporary_file.hpp: removed
// on every exit short of SIGKILL) and renames it over `path` in finish(),
// after reading it back: the file is synced and its frames are counted, so a
// video cut short by a full disk is caught. Destroyed unfinished (cancelled,
// failed), it removes the staging file, so a partial video is never seen.
class VideoSequence {
 public:
  VideoSequence(std::filesystem::path path, double fps, VideoCodec codec);
  ~VideoSequence();
  VideoSequence(const VideoSequence&) = delete;
  VideoSequence& operator=(const VideoSequence&) = delete;

  // 8-bit sRGB-encoded; 1, 3 or 4 channels (alpha dropped). Every frame must
  // have the size of the first (else loom::Error); odd sizes are padded to
  // even ones (H.264's 4:2:0 chroma needs them) by repeating the last row or
  // column.
  void add(const Image& frame);
  void finish();

  const std::string& codec_name() const { return codec_name_; }  // "avc1 (H.264)" or "mp4v (MPEG-4 Part 2)"
  int frames() const { return frames_; }

 private:
  void open(int width, int height);
  void verify() const;
  std::filesystem::path path_;
  std::unique_ptr<TemporaryFile> temp_;
  double fps_;
  VideoCodec codec_;
  std::unique_ptr<VideoEncoder> encoder_;
  std::string codec_name_;
  int width_ = 0, height_ = 0, frames_ = 0;
  int frame_width_ = 0, frame_height_ = 0;  // before padding
  bool finished_ = false;
};

}  // namespace loom::io
