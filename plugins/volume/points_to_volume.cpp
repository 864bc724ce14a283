// PointsToVolume: particles (an MPM state's MPMPoints, any point set) as a
// density and a velocity grid, splatted with MPM's quadratic B-spline.
#include "bspline_splat.hpp"
#include "loom/plugin.hpp"

namespace {

using loom::volume::Volume;

// The attribute `name` with `columns` columns, or an empty matrix.
Eigen::MatrixXd attribute(const loom::PointSet& points, const std::string& name, int columns) {
  for (const loom::PointAttribute& a : points.attributes)
    if (a.name == name) {
      if (a.values.cols() != columns)
        throw loom::Error("attribute '" + name + "' has " + std::to_string(a.values.cols()) + " columns, not " +
                          std::to_string(columns));
      return a.values;
    }
  return {};
}

struct PointsToVolume {
  static constexpr const char* name = "PointsToVolume";
  static void declare(loom::NodeSpec& s) {
    s.describe("Splats points onto a sparse voxel grid with the quadratic B-spline of MLS-MPM (MPMStep's "
               "kernel): a density grid (mass per voxel volume; its sum times the voxel volume is the points' "
               "mass) and, when the points have a 'velocity' attribute, the mass-weighted velocity as a vector "
               "grid. Masses are the points' 'mass' attribute (MPMPoints writes it), else point_mass each. "
               "Voxel (i, j, k) is centred at (i, j, k) times voxel_size. SaveVDB writes the grids.")
        .input<loom::PointSet>("points", "the points, e.g. MPMPoints' points")
        .input<double>("voxel_size", 0.01,
                       "voxel edge length (domain units; MPMStep's Δx = size / resolution "
                       "gives MPM's own grid)")
        .at_least(1e-6)
        .input<double>("point_mass", 1.0, "the mass of every point when the points have no 'mass' attribute")
        .at_least(0)
        .output<Volume>("volume", "grids 'density' (float) and 'velocity' (vec3s, if the points had velocities)");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    const auto& points = in.get<loom::PointSet>("points");
    const double h = in.get<double>("voxel_size");
    Eigen::VectorXd mass = attribute(points, "mass", 1);
    if (mass.size() == 0) mass = Eigen::VectorXd::Constant(points.points(), in.get<double>("point_mass"));
    if (mass.size() > 0 && mass.minCoeff() < 0) throw loom::Error("a point has a negative mass");
    const Eigen::MatrixX3d velocity = attribute(points, "velocity", 3);
    ctx.check_cancelled();
    out.set("volume", loom::volume::splat_points(points.P, mass, velocity, h));
  }
};
LOOM_NODE(PointsToVolume);

}  // namespace
