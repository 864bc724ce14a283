#include "video_codec.hpp"

#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <unistd.h>
#include <opencv2/imgproc.hpp>

#include "video_files.hpp"

namespace loom::io {
namespace fs = std::filesystem;

VideoSequence::VideoSequence(fs::path path, double fps, VideoCodec codec)
    : path_(std::move(path)), fps_(fps), codec_(codec) {
  if (!(fps_ > 0) || fps_ > 1000) throw Error("fps must be between 0 and 1000, got " + std::to_string(fps_));
  const std::string ext = path_.extension().string();
  if (ext != ".mp4" && ext != ".MP4") throw Error("cannot save " + path_.string() + ": SaveVideo writes .mp4 files");
  temp_ = std::make_unique<TemporaryFile>(path_, ".mp4");
}

VideoSequence::~VideoSequence() {
  if (finished_) return;
  encoder_.reset();  // closes the staging file before it is removed
  temp_->discard();
}

void VideoSequence::open(int width, int height) {
  std::error_code ec;
  if (path_.has_parent_path()) fs::create_directories(path_.parent_path(), ec);
  if (ec) throw Error("cannot create folder " + path_.parent_path().string() + ": " + ec.message());
  // Try the folder first, so a read-only or missing one is named as such, in
  // the system's words, not as a codec's failure.
  const int fd = ::open(temp_->path().c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd < 0) throw Error("cannot write " + path_.string() + ": " + std::strerror(errno));
  ::close(fd);
  const VideoFiles& ffmpeg = video_files();
  const bool h264 = codec_ != VideoCodec::mpeg4 && ffmpeg.available(VideoEncoder::Codec::h264);
  if (codec_ == VideoCodec::h264 && !h264)
    throw Error("this FFmpeg cannot encode H.264 (libx264): use codec \"mp4v\" or \"auto\"");
  encoder_ =
      ffmpeg.open(temp_->path(), h264 ? VideoEncoder::Codec::h264 : VideoEncoder::Codec::mpeg4, width, height, fps_);
  codec_name_ = h264 ? "avc1 (H.264)" : "mp4v (MPEG-4 Part 2)";
}

void VideoSequence::add(const Image& frame) {
  if (frame.empty()) throw Error("the image is empty: nothing to add to the video");
  require_finite(frame, "the image");
  const int width = frame.width() + frame.width() % 2, height = frame.height() + frame.height() % 2;
  if (!encoder_) {
    open(width, height);
    width_ = width;
    height_ = height;
    frame_width_ = frame.width();
    frame_height_ = frame.height();
  } else if (frame.width() != frame_width_ || frame.height() != frame_height_) {
    throw Error("frame " + std::to_string(frames_ + 1) + " is " + std::to_string(frame.width()) + "x" +
                std::to_string(frame.height()) + " but the video's frames are " + std::to_string(frame_width_) + "x" +
                std::to_string(frame_height_) + ": every frame must have the same size");
  }
  cv::Mat m = with_encoding(frame, Encoding::srgb).pixels;
  cv::Mat rgb;
  switch (m.channels()) {
    case 1:
      cv::cvtColor(m, rgb, cv::COLOR_GRAY2RGB);
      break;
    case 2: {
      cv::Mat gray;
      cv::extractChannel(m, gray, 0);
      cv::cvtColor(gray, rgb, cv::COLOR_GRAY2RGB);
      break;
    }
    case 3:
      rgb = m;
      break;
    default:
      cv::cvtColor(m, rgb, cv::COLOR_RGBA2RGB);
      break;
  }
  rgb.convertTo(rgb, CV_8U, 255.0);  // saturates to [0, 255]
  if (rgb.cols != width_ || rgb.rows != height_)
    cv::copyMakeBorder(rgb, rgb, 0, height_ - rgb.rows, 0, width_ - rgb.cols, cv::BORDER_REPLICATE);
  if (!rgb.isContinuous()) rgb = rgb.clone();
  encoder_->write_rgb(rgb.ptr<std::uint8_t>());
  ++frames_;
}

void VideoSequence::finish() {
  if (!encoder_) throw Error("no frames: nothing to write to " + path_.string());
  try {
    encoder_->finish();
  } catch (const Error& e) {
    throw Error("cannot write " + path_.string() + ": " + e.what());
  }
  encoder_.reset();
  verify();
  temp_->commit();
  finished_ = true;
}

// The whole file on the disk (fsync checked) and every frame readable back.
void VideoSequence::verify() const {
  const std::string fail = "cannot write " + path_.string() + ": ";
  const int fd = ::open(temp_->path().c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw Error(fail + std::strerror(errno));
  const bool synced = ::fsync(fd) == 0;
  const int error = errno;
  ::close(fd);
  if (!synced) throw Error(fail + std::strerror(error));
  const int count = video_files().count_frames(temp_->path());
  if (count != frames_)
    throw Error(fail + "the encoder's file holds " + std::to_string(count) + " of " + std::to_string(frames_) +
                " frames (is the disk full, or a file size limit reached?)");
}

}  // namespace loom::io
