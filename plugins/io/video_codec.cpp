#include "video_codec.hpp"

#include <atomic>

#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <unistd.h>

namespace loom::io {
namespace fs = std::filesystem;

VideoSequence::VideoSequence(fs::path path, double fps, VideoCodec codec)
    : path_(std::move(path)), fps_(fps), codec_(codec) {
  static std::atomic<unsigned> counter{0};
  if (!(fps_ > 0) || fps_ > 1000) throw Error("fps must be between 0 and 1000, got " + std::to_string(fps_));
  const std::string ext = path_.extension().string();
  if (ext != ".mp4" && ext != ".MP4") throw Error("cannot save " + path_.string() + ": SaveVideo writes .mp4 files");
  temp_ = path_.parent_path() / ("." + path_.stem().string() + ".tmp" + std::to_string(::getpid()) + "." +
                                 std::to_string(counter++) + ".mp4");
}

VideoSequence::~VideoSequence() {
  if (finished_) return;
  if (writer_) writer_->release();
  std::error_code ec;
  fs::remove(temp_, ec);
}

void VideoSequence::open(int width, int height) {
  std::error_code ec;
  if (path_.has_parent_path()) fs::create_directories(path_.parent_path(), ec);
  if (ec) throw Error("cannot create folder " + path_.parent_path().string() + ": " + ec.message());
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
      writer->open(temp_.string(), cv::CAP_FFMPEG,
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
    fs::remove(temp_, ec);
  }
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
  } else if (width != width_ || height != height_) {
    throw Error("frame " + std::to_string(frames_ + 1) + " is " + std::to_string(frame.width()) + "x" +
                std::to_string(frame.height()) + " but the video's frames are " + std::to_string(width_) + "x" +
                std::to_string(height_) + ": every frame must have the same size");
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
  std::error_code ec;
  fs::rename(temp_, path_, ec);
  if (ec) throw Error("cannot write " + path_.string() + ": " + ec.message());
  finished_ = true;
}

}  // namespace loom::io
