// SaveVideo: the frames of a run as one MP4, written in order and renamed into
// place at the last frame.
#include "loom/plugin.hpp"
#include "video_codec.hpp"

namespace {

struct SaveVideo {
  static constexpr const char* name = "SaveVideo";
  static void declare(loom::NodeSpec& s) {
    s.describe("Writes the image of every frame of the run, in order, as one MP4 video: H.264 (avc1) "
               "where FFmpeg has libx264, else MPEG-4 Part 2 (mp4v). The file appears at the "
               "run's last frame (a temporary file renamed); a cancelled or failed run leaves none. One encoder "
               "thread and fixed settings: the same frames give the same bytes whatever cores the process sees.")
        .set_sequence_sink()
        .input<loom::Image>("image", "this frame's image (every frame the same size)")
        .input<std::string>("path", "the .mp4 file to write, relative to the output folder")
        .output_file()
        .input<double>("fps", 0.0, "frames per second; 0: the graph's rate")
        .range(0, 1000)
        .enum_input("codec", loom::io::VideoCodec::automatic,
                    {{loom::io::VideoCodec::automatic, "auto"},
                     {loom::io::VideoCodec::h264, "h264"},
                     {loom::io::VideoCodec::mpeg4, "mp4v"}},
                    "auto: H.264 if available, else mp4v");
  }
  static void run(loom::Inputs& in, loom::Outputs&, loom::Context& ctx) {
    const auto& t = ctx.time();
    auto video = ctx.sequence_state<loom::io::VideoSequence>([&] {
      const double fps = in.get<double>("fps") > 0 ? in.get<double>("fps") : t.fps;
      return std::make_shared<loom::io::VideoSequence>(in.get<std::string>("path"), fps,
                                                       in.get<loom::io::VideoCodec>("codec"));
    });
    video->add(in.get<loom::Image>("image"));
    ctx.progress(t.frame - t.first + 1, t.last - t.first + 1, "frame " + std::to_string(t.frame));
    if (t.frame == t.last) {
      video->finish();
      ctx.log("wrote " + in.get<std::string>("path") + " (" + std::to_string(video->frames()) + " frames, " +
              video->codec_name() + ")");
    }
  }
};
LOOM_NODE(SaveVideo);

}  // namespace
