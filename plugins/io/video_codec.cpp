#include "video_codec.hpp"

#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <unistd.h>

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
  if (writer_) writer_->release();
  temp_->discard();
}

void VideoSequence::open(int width, int height) {
  std::error_code ec;
  if (path_.has_parent_path()) fs::create_directories(path_.parent_path(), ec);
  if (ec) throw Error("cannot create folder " + path_.parent_path().string() + ": " + ec.message());
  // OpenCV says only "cannot open" for any failure: try the folder first, so
  // a read-only or missing one is named as such, not as a missing codec.
  const int fd = ::open(temp_->path().c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd < 0) throw Error("cannot write " + path_.string() + ": " + std::strerror(errno));
  ::close(fd);
  struct Choice {
    const char* fourcc;
    const char* name;
  };
  std::vector<Choice> choices;
  if (codec_ != VideoCodec::mpeg4) choices.push_back({"avc1", "avc1 (H.264)"});
  if (codec_ != VideoCodec::h264) choices.push_back({"mp4v", "mp4v (MPEG-4 Part 2)"});
  for (const Choice& c : choices) {
    auto writer = std::make_unique<cv::VideoWriter>();
    try {
      writer->open(temp_->path().string(), cv::CAP_FFMPEG,
                   cv::VideoWriter::fourcc(c.fourcc[0], c.fourcc[1], c.fourcc[2], c.fourcc[3]), fps_,
                   cv::Size(width, height), true);
    } catch (const cv::Exception&) {
      continue;
    }
    if (writer->isOpened()) {
      writer_ = std::move(writer);
      codec_name_ = c.name;
      return;
    }
  }
  temp_->discard();
  throw Error(std::string("OpenCV's FFmpeg backend cannot encode ") +
              (codec_ == VideoCodec::h264 ? "H.264" : codec_ == VideoCodec::mpeg4 ? "MPEG-4" : "H.264 or MPEG-4") +
              " video here (is libopencv-videoio built with FFmpeg?)");
}

void VideoSequence::add(const Image& frame) {
  if (frame.empty()) throw Error("the image is empty: nothing to add to the video");
  require_finite(frame, "the image");
  const int width = frame.width() + frame.width() % 2, height = frame.height() + frame.height() % 2;
  if (!writer_) {
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
  cv::Mat bgr;
  switch (m.channels()) {
    case 1: cv::cvtColor(m, bgr, cv::COLOR_GRAY2BGR); break;
    case 2: {
      cv::Mat gray;
      cv::extractChannel(m, gray, 0);
      cv::cvtColor(gray, bgr, cv::COLOR_GRAY2BGR);
      break;
    }
    case 3: cv::cvtColor(m, bgr, cv::COLOR_RGB2BGR); break;
    default: cv::cvtColor(m, bgr, cv::COLOR_RGBA2BGR); break;
  }
  bgr.convertTo(bgr, CV_8U, 255.0);  // saturates to [0, 255]
  if (bgr.cols != width_ || bgr.rows != height_)
    cv::copyMakeBorder(bgr, bgr, 0, height_ - bgr.rows, 0, width_ - bgr.cols, cv::BORDER_REPLICATE);
  writer_->write(bgr);
  ++frames_;
}

void VideoSequence::finish() {
  if (!writer_) throw Error("no frames: nothing to write to " + path_.string());
  writer_->release();
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
  cv::VideoCapture check(temp_->path().string(), cv::CAP_FFMPEG);
  const double count = check.isOpened() ? check.get(cv::CAP_PROP_FRAME_COUNT) : 0;
  if (static_cast<int>(count) != frames_)
    throw Error(fail + "the encoder's file holds " + std::to_string(static_cast<int>(count)) + " of " +
                std::to_string(frames_) + " frames (is the disk full, or a file size limit reached?)");
}

}  // namespace loom::io
