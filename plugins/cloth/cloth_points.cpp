// ClothPoints: a cloth state's numbers as points, for SavePoints.
#include "cloth_state.hpp"
#include "loom/plugin.hpp"

namespace {

struct ClothPoints {
  static constexpr const char* name = "ClothPoints";
  static void declare(loom::NodeSpec& s) {
    s.describe("A cloth state as points: the vertex positions with the attributes velocity (m/s), mass (kg) "
               "and fixed (1 held, 0 free), and the system's colors; SavePoints writes them as a PLY.")
        .input<loom::cloth::ClothState>("state", "a ClothStep's (or a system node's) state")
        .output<loom::PointSet>("points", "one point per vertex");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    out.set("points", loom::cloth::state_points(in.get<loom::cloth::ClothState>("state")));
  }
};
LOOM_NODE(ClothPoints);

}  // namespace
