// Time: the frame being evaluated, for animating anything from a graph.
#include "loom/plugin.hpp"

namespace {

struct Time {
  static constexpr const char* name = "Time";
  static void declare(loom::NodeSpec& s) {
    s.describe("The frame being evaluated and its time in seconds since the graph's start frame "
               "((frame - start) / fps). Time-dependent: what depends on it is evaluated per frame; "
               "everything else once.")
        .set_time_dependent()
        .output<int>("frame", "the frame number")
        .output<double>("seconds", "seconds since the start frame");
  }
  static void run(loom::Inputs&, loom::Outputs& out, loom::Context& ctx) {
    out.set("frame", ctx.time().frame);
    out.set("seconds", ctx.time().seconds());
  }
};
LOOM_NODE(Time);

}  // namespace
