// MPMPoints: an MPM state's numbers as points, for SavePoints.
#include "loom/plugin.hpp"
#include "mpm_state.hpp"

namespace {

struct MPMPoints {
  static constexpr const char* name = "MPMPoints";
  static void declare(loom::NodeSpec& s) {
    s.describe("The particles of an MPM state as points with their numbers: velocity (m/s), mass, volume "
               "(rest), J (volume ratio), snow_plastic_J, plastic_strain (sand's hardening state q) and "
               "material (0 fluid, 1 elastic, 2 snow, 3 sand); SavePoints writes them as PLY properties.")
        .input<loom::mpm::MpmState>("state", "an MPMStep's state")
        .input<double>("radius", 0.002, "radius of every point (domain units, as MPMStep's point_radius)").at_least(0)
        .output<loom::PointSet>("points", "one point per particle (z = 0 in 2D)");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    out.set("points", loom::mpm::particle_points(in.get<loom::mpm::MpmState>("state"), in.get<double>("radius")));
  }
};
LOOM_NODE(MPMPoints);

}  // namespace
