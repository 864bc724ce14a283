#include "map_inputs.hpp"

#include <memory>

#include "control_points.hpp"
#include "idw.hpp"
#include "loom/point_pairs.hpp"
#include "rbf.hpp"

namespace loom::warp {

namespace {
constexpr double kMergeDistance = 1e-3;  // pixels: closer sources are one point
enum class Method { idw, rbf };
enum class IdwAffine { fitted, zero };
}  // namespace

void declare_map_inputs(NodeSpec& s) {
  s.input<PointPairs>("pairs", PointPairs{}, "control points p_i → q_i in pixels (none: identity)")
      .enum_input("method", Method::rbf, {{Method::idw, "idw"}, {Method::rbf, "rbf"}},
                  "inverse distance weighting or radial basis functions")
      .input<double>("idw_power", 2.0, "IDW: μ in σ_i = 1/‖x − p_i‖^μ").range(0.1, 16)
      .enum_input("idw_affine", IdwAffine::fitted, {{IdwAffine::fitted, "fitted"}, {IdwAffine::zero, "zero"}},
                  "IDW: local affine parts D_i fitted by weighted least squares, or D_i = 0")
      .enum_input("rbf_kernel", RbfKernel::multiquadric,
                  {{RbfKernel::multiquadric, "multiquadric"}, {RbfKernel::thin_plate, "thin_plate"}},
                  "RBF: (d² + r_i²)^(μ/2) with the assignment's affine rule, or d² log d")
      .input<double>("rbf_exponent", 1.0, "RBF multiquadric: μ (1 = multiquadric, −1 = inverse)").range(-4, 4)
      .input<double>("lambda", 0.0, "RBF: regularization λ added to the kernel matrix (0 = interpolate)")
      .range(0, 1e12);
}

RowMap fit_map(Inputs& in, Context& ctx, MapDirection direction) {
  const PointPairs& pairs = in.get<PointPairs>("pairs");
  const auto n = static_cast<Eigen::Index>(pairs.size());
  Eigen::MatrixX2d P(n, 2), Q(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) {
    P.row(i) = pairs.p[static_cast<std::size_t>(i)].transpose();
    Q.row(i) = pairs.q[static_cast<std::size_t>(i)].transpose();
  }
  if (direction == MapDirection::inverse) std::swap(P, Q);
  std::vector<std::string> notes;
  const ControlPoints cp = clean_control_points(P, Q, kMergeDistance, &notes);

  RowMap map;
  if (in.get<Method>("method") == Method::idw) {
    auto m = std::make_shared<const IdwMap>(fit_idw(cp.p, cp.q, in.get<double>("idw_power"),
                                                    in.get<IdwAffine>("idw_affine") == IdwAffine::fitted));
    map = [m](double y, const double* x, int k, double* fx, double* fy) { evaluate_idw_row(*m, y, x, k, fx, fy); };
  } else {
    const RbfKernel kernel = in.get<RbfKernel>("rbf_kernel");
    auto m = std::make_shared<const RbfMap>(
        fit_rbf(cp.p, cp.q, kernel, in.get<double>("rbf_exponent"), in.get<double>("lambda"), &notes));
    map = [m](double y, const double* x, int k, double* fx, double* fy) { evaluate_rbf_row(*m, y, x, k, fx, fy); };
  }
  for (const std::string& note : notes) ctx.warn(note);
  return map;
}

}  // namespace loom::warp
