// PoissonBlend: seamless cloning. Solves eq. 7 of Pérez et al. 2003 (see
// poisson_system.hpp) per channel with one matrix for all channels, and keeps
// the factorization (or multigrid hierarchy) keyed by the region's shape, so
// moving the region (a new offset) only re-solves.
#include <memory>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "exact_poisson.hpp"
#include "loom/image.hpp"
#include "loom/plugin.hpp"
#include "multigrid.hpp"
#include "poisson_system.hpp"

namespace {

using loom::Error;
using loom::Image;
using namespace loom::poisson;

enum class PoissonSolver { multigrid, cholmod };

// The region as a source-sized mask from whichever of mask / rectangle /
// polygon is set (exactly one must be).
cv::Mat1b region_mask(loom::Inputs& in, cv::Size source) {
  const int given = int(in.has("mask")) + int(in.has("rectangle")) + int(in.has("polygon"));
  if (given != 1)
    throw Error("give the region as exactly one of mask, rectangle or polygon (" +
                std::to_string(given) + " are set)");
  cv::Mat1b region = cv::Mat1b::zeros(source);
  if (in.has("mask")) {
    const Image& mask = in.get<Image>("mask");
    if (mask.pixels.size() != source)
      throw Error("mask is " + std::to_string(mask.width()) + "x" + std::to_string(mask.height()) +
                  " but the source is " + std::to_string(source.width) + "x" +
                  std::to_string(source.height) + ": they must match");
    loom::require_finite(mask, "mask");
    cv::Mat first;
    cv::extractChannel(mask.pixels, first, 0);
    region = first >= 0.5f;
  } else if (in.has("rectangle")) {
    const auto& r = in.get<std::vector<int>>("rectangle");
    if (r.size() != 4 || r[2] <= 0 || r[3] <= 0)
      throw Error("rectangle must be [x, y, width, height] with a positive width and height");
    region(cv::Rect(r[0], r[1], r[2], r[3]) & cv::Rect({0, 0}, source)).setTo(255);
  } else {
    const auto& points = in.get<std::vector<loom::Vec2>>("polygon");
    if (points.size() < 3) throw Error("polygon needs at least 3 points");
    std::vector<cv::Point> ring;
    for (const loom::Vec2& p : points) {
      if (!p.allFinite()) throw Error("polygon has a NaN or infinite point");
      ring.emplace_back(cvRound(p.x() * 256), cvRound(p.y() * 256));  // 8 fractional bits
    }
    cv::fillPoly(region, std::vector<std::vector<cv::Point>>{ring}, 255, cv::LINE_8, 8);
  }
  return region;
}

struct PoissonBlend {
  static constexpr const char* name = "PoissonBlend";
  static void declare(loom::NodeSpec& s) {
    s.describe("Seamless cloning (Pérez et al. 2003): pastes the source's gradients inside a "
               "region onto the target, solving the Poisson equation with the target as boundary.")
        .set_version(1)
        .input<Image>("source", "the image whose region is cloned")
        .input<Image>("target", "the image it is cloned onto (the boundary values f*)")
        .input<Image>("mask", "the region: source-sized, pixels ≥ 0.5 in the first channel")
        .optional()
        .input<std::vector<int>>("rectangle", "the region: [x, y, width, height] in the source")
        .optional()
        .input<std::vector<loom::Vec2>>("polygon", "the region: polygon vertices in source pixels")
        .optional()
        .input<loom::Vec2i>("offset", loom::Vec2i(0, 0),
                            "source pixel (x, y) lands on target pixel (x, y) + offset")
        .enum_input("mode", Guidance::normal, {{Guidance::normal, "normal"}, {Guidance::mixed, "mixed"}},
                    "guidance: the source's gradient, or per edge the stronger of source and target")
        .enum_input("solver", PoissonSolver::multigrid,
                    {{PoissonSolver::multigrid, "multigrid"}, {PoissonSolver::cholmod, "cholmod"}},
                    "multigrid-preconditioned CG (fast), or an exact sparse Cholesky (CHOLMOD)")
        .input<double>("tolerance", 2e-3,
                       "multigrid: stop when an iteration changes no pixel by more than this")
        .range(1e-8, 0.1)
        .output<Image>("image", "the target with the region blended in");
  }

  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    const Image& target = in.get<Image>("target");
    Image source = in.get<Image>("source");
    if (source.empty() || target.empty()) throw Error("source and target must not be empty");
    if (source.channels() != target.channels())
      throw Error("source has " + std::to_string(source.channels()) + " channels, target " +
                  std::to_string(target.channels()) + ": convert one so they match");
    loom::require_finite(source, "source");
    loom::require_finite(target, "target");
    if (source.space != target.space)
      throw Error("source is " + loom::describe_space(source) + ", target " + loom::describe_space(target) +
                  ": ColorConvert one so they are in the same colour space");
    if (source.encoding != target.encoding) {
      ctx.warn("source and target have different encodings: the source is converted to the "
               "target's");
      source = loom::with_encoding(source, target.encoding);
    }

    const loom::Vec2i offset_in = in.get<loom::Vec2i>("offset");
    const cv::Point offset(offset_in.x(), offset_in.y());
    const BlendRegion region =
        place_region(region_mask(in, source.pixels.size()), offset, target.pixels.size());
    if (region.clipped_source)
      ctx.warn("the region touches the source's border: those pixels are left out (their "
               "gradient needs pixels outside the source)");
    if (region.clipped_target) ctx.warn("part of the region lands outside the target and is clipped");

    const Guidance mode = in.get<Guidance>("mode");
    const cv::Mat b = poisson_rhs(region, target.pixels, source.pixels, offset, mode);
    cv::Mat f = source_on_rect(region, source.pixels, offset);
    const PoissonSolver solver = in.get<PoissonSolver>("solver");
    const std::uint64_t key = loom::Hasher(region_key(region)).pod(static_cast<int>(solver)).digest();
    if (solver == PoissonSolver::cholmod) {
      ctx.progress(0, 1, "factoring");
      auto exact = ctx.scratch<ExactPoisson>(key, [&] { return std::make_shared<ExactPoisson>(region.unknown); });
      exact->solve(b, f);
    } else {
      auto mg = ctx.scratch<MultigridPoisson>(key, [&] { return std::make_shared<MultigridPoisson>(region.unknown); });
      const int max_iterations = 200;
      const auto result = mg->solve(b, f, in.get<double>("tolerance"), max_iterations,
                                    MultigridPoisson::Start::previous_correction,
                                    [&] { ctx.check_cancelled(); });
      if (result.last_change > in.get<double>("tolerance"))
        ctx.warn("multigrid stopped after " + std::to_string(max_iterations) +
                 " iterations with changes of " + std::to_string(result.last_change));
    }
    cv::Mat image = target.pixels.clone();
    f.copyTo(image(region.rect), region.unknown);
    out.set("image", target.like(image));
  }
};
LOOM_NODE(PoissonBlend);

}  // namespace
