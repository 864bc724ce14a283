// SavePoints: writes a point set as a PLY point cloud, atomically.
#include "loom/plugin.hpp"
#include "point_cloud_codec.hpp"

namespace {

struct SavePoints {
  static constexpr const char* name = "SavePoints";
  static void declare(loom::NodeSpec& s) {
    s.describe("Writes a point set (particles, a point cloud) as a binary little-endian PLY: float x y z, "
               "and, when the points have them, uchar red green blue (sRGB-encoded), a float radius and "
               "one property per attribute column (mass; velocity_x velocity_y velocity_z). Nothing on "
               "disk changes unless the whole write succeeds.")
        .set_sink()
        .input<loom::PointSet>("points", "the points to write")
        .input<std::string>("path", "the .ply file to write, relative to the output folder; {frame:04} in it becomes "
                                    "the frame number (one file per frame)")
        .output_file()
        .input<bool>("colors", true, "write red green blue (if the points have colors)")
        .input<bool>("radius", true, "write a radius property (if the points have radii)")
        .input<bool>("attributes", true, "write the points' named attributes (velocity, mass, ...), if any")
        .input<bool>("double_precision", false,
                     "write positions, radius and attributes as 64-bit doubles (exact) instead of floats");
  }
  static void run(loom::Inputs& in, loom::Outputs&, loom::Context& ctx) {
    const std::string& path = in.get<std::string>("path");
    ctx.check_cancelled();
    loom::io::write_point_cloud(in.get<loom::PointSet>("points"), path,
                                {in.get<bool>("colors"), in.get<bool>("radius"), in.get<bool>("attributes"),
                                 in.get<bool>("double_precision")});
    ctx.log("wrote " + path);
  }
};
LOOM_NODE(SavePoints);

}  // namespace
