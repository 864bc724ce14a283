// lib/libloom_video_files.so: MP4 files through FFmpeg (libavcodec,
// libavformat, libswscale; video_files.hpp says why a library of its own).
#include <climits>
#include <cmath>
#include <mutex>
#include <string>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include "loom/error.hpp"
#include "video_files.hpp"

namespace loom::io {

namespace {

std::string av_message(int code) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(code, text, sizeof text);
  return text;
}

void check(int code, const std::string& what) {
  if (code < 0) throw Error("FFmpeg cannot " + what + ": " + av_message(code));
}

const char* encoder_name(VideoEncoder::Codec codec) { return codec == VideoEncoder::Codec::h264 ? "libx264" : "mpeg4"; }

// The time base OpenCV's writer chose (cap_ffmpeg_impl.hpp): the frame rate as
// a fraction with a power-of-ten denominator, within 0.001 of it. Kept so the
// timestamps of a video are those SaveVideo wrote before.
AVRational frame_rate(double fps) {
  int rate = static_cast<int>(fps + 0.5), base = 1;
  while (std::fabs(static_cast<double>(rate) / base - fps) > 0.001 && base < 100000) {
    base *= 10;
    rate = static_cast<int>(fps * base + 0.5);
  }
  return AVRational{rate, base};
}

// x264 prints its statistics at AV_LOG_INFO; Loom prints FFmpeg's errors only,
// as OpenCV's backend did.
void quiet_ffmpeg() {
  static std::once_flag once;
  std::call_once(once, [] { av_log_set_level(AV_LOG_ERROR); });
}

// FFmpeg's contexts for one MP4 being written.
struct State {
  AVFormatContext* format = nullptr;
  AVCodecContext* codec = nullptr;
  AVStream* stream = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* packet = nullptr;
  SwsContext* scale = nullptr;
  int width = 0, height = 0;
  std::int64_t next_pts = 0;
  bool header_written = false;

  ~State() {
    sws_freeContext(scale);
    av_packet_free(&packet);
    av_frame_free(&frame);
    avcodec_free_context(&codec);
    if (format) {
      if (format->pb) avio_closep(&format->pb);
      avformat_free_context(format);
    }
  }

  // Sends every packet the encoder has ready to the muxer.
  void drain() {
    for (;;) {
      const int r = avcodec_receive_packet(codec, packet);
      if (r == AVERROR(EAGAIN) || r == AVERROR_EOF) return;
      check(r, "encode a frame");
      av_packet_rescale_ts(packet, codec->time_base, stream->time_base);
      packet->stream_index = stream->index;
      check(av_interleaved_write_frame(format, packet), "write a frame");
    }
  }
};

class FfmpegEncoder final : public VideoEncoder {
 public:
  FfmpegEncoder(const std::filesystem::path& file, Codec codec, int width, int height, double fps);
  void write_rgb(const std::uint8_t* rgb) override;
  void finish() override;

 private:
  State s_;
};

// Every choice is fixed here, for bytes that depend on the frames only:
// - one encoder thread: libavcodec's libx264 wrapper defaults to
//   "threads=auto", which x264 sizes from the CPUs the process may run on
//   (sched_getaffinity: 1 under `taskset -c 0`, 3 on two cores), and x264's
//   output depends on its thread count (frame threads search references that
//   are not finished yet); OpenCV 4.6's writer offers no way to set it;
// - bit-exact muxing and coding (no library version strings in the file) and
//   bit-exact colour conversion (no CPU-dependent SIMD rounding);
// - OpenCV's former settings otherwise: CRF 23 for H.264, twice fps*w*h bits
//   per second, quantizer from 3 and a key frame every 12 frames for MPEG-4.
FfmpegEncoder::FfmpegEncoder(const std::filesystem::path& file, Codec codec, int width, int height, double fps) {
  quiet_ffmpeg();
  const AVCodec* encoder = avcodec_find_encoder_by_name(encoder_name(codec));
  if (!encoder) throw Error(std::string("this FFmpeg has no ") + encoder_name(codec) + " encoder");
  State& s = s_;
  s.width = width;
  s.height = height;
  check(avformat_alloc_output_context2(&s.format, nullptr, "mp4", file.c_str()), "set up an MP4 file");
  s.format->flags |= AVFMT_FLAG_BITEXACT;
  s.codec = avcodec_alloc_context3(encoder);
  if (!s.codec) throw Error("FFmpeg cannot allocate an encoder");
  AVCodecContext& c = *s.codec;
  const AVRational rate = frame_rate(fps);
  c.width = width;
  c.height = height;
  c.time_base = AVRational{rate.den, rate.num};
  c.framerate = rate;
  c.pix_fmt = AV_PIX_FMT_YUV420P;
  c.thread_count = 1;
  c.flags |= AV_CODEC_FLAG_BITEXACT;
  if (s.format->oformat->flags & AVFMT_GLOBALHEADER) c.flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
  if (codec == Codec::h264) {
    check(av_opt_set(c.priv_data, "crf", "23", 0), "set H.264's quality");
  } else {
    const double bits = std::min(2.0 * fps * width * height, static_cast<double>(INT_MAX));
    c.bit_rate = static_cast<std::int64_t>(bits);
    c.bit_rate_tolerance = static_cast<int>(bits);
    c.qmin = 3;
    c.gop_size = 12;
  }
  check(avcodec_open2(s.codec, encoder, nullptr), std::string("open the ") + encoder_name(codec) + " encoder");
  s.stream = avformat_new_stream(s.format, nullptr);
  if (!s.stream) throw Error("FFmpeg cannot add a video stream");
  s.stream->time_base = c.time_base;
  s.stream->avg_frame_rate = rate;
  check(avcodec_parameters_from_context(s.stream->codecpar, s.codec), "describe the video stream");
  check(avio_open(&s.format->pb, file.c_str(), AVIO_FLAG_WRITE), "open " + file.string());
  check(avformat_write_header(s.format, nullptr), "write the MP4 header");
  s.header_written = true;
  s.frame = av_frame_alloc();
  s.packet = av_packet_alloc();
  if (!s.frame || !s.packet) throw Error("FFmpeg cannot allocate a frame");
  s.frame->format = c.pix_fmt;
  s.frame->width = width;
  s.frame->height = height;
  check(av_frame_get_buffer(s.frame, 0), "allocate a frame");
  s.scale = sws_getContext(width, height, AV_PIX_FMT_RGB24, width, height, AV_PIX_FMT_YUV420P,
                           SWS_BICUBIC | SWS_BITEXACT | SWS_ACCURATE_RND, nullptr, nullptr, nullptr);
  if (!s.scale) throw Error("FFmpeg cannot convert RGB to YUV 4:2:0");
}

void FfmpegEncoder::write_rgb(const std::uint8_t* rgb) {
  State& s = s_;
  check(av_frame_make_writable(s.frame), "reuse a frame");
  const std::uint8_t* source[1] = {rgb};
  const int stride[1] = {3 * s.width};
  sws_scale(s.scale, source, stride, 0, s.height, s.frame->data, s.frame->linesize);
  s.frame->pts = s.next_pts++;
  check(avcodec_send_frame(s.codec, s.frame), "encode a frame");
  s.drain();
}

void FfmpegEncoder::finish() {
  State& s = s_;
  check(avcodec_send_frame(s.codec, nullptr), "finish encoding");
  s.drain();
  check(av_write_trailer(s.format), "write the MP4 index");
  check(avio_closep(&s.format->pb), "close the video file");
}

bool available(VideoEncoder::Codec codec) { return avcodec_find_encoder_by_name(encoder_name(codec)) != nullptr; }

std::unique_ptr<VideoEncoder> open(const std::filesystem::path& file, VideoEncoder::Codec codec, int width, int height,
                                   double fps) {
  return std::make_unique<FfmpegEncoder>(file, codec, width, height, fps);
}

int count_frames(const std::filesystem::path& file) {
  quiet_ffmpeg();
  AVFormatContext* format = nullptr;
  if (avformat_open_input(&format, file.c_str(), nullptr, nullptr) < 0) return 0;
  int count = 0;
  const int stream = av_find_best_stream(format, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
  AVPacket* packet = av_packet_alloc();
  while (stream >= 0 && packet && av_read_frame(format, packet) >= 0) {
    if (packet->stream_index == stream) ++count;
    av_packet_unref(packet);
  }
  av_packet_free(&packet);
  avformat_close_input(&format);
  return count;
}

const VideoFiles kTable = {kVideoFilesVersion, &available, &open, &count_frames};

}  // namespace
}  // namespace loom::io

extern "C" __attribute__((visibility("default"))) const loom::io::VideoFiles* loom_video_files() {
  return &loom::io::kTable;
}
