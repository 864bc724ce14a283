// The discrete Poisson equation of seamless cloning (Pérez, Gangnet, Blake
// 2003, eq. 7), set up on a grid around the region Ω in target pixels:
//
//   |N_p| f_p − Σ_{q∈N_p∩Ω} f_q = Σ_{q∈N_p∩∂Ω} f*_q + Σ_{q∈N_p} v_pq,   p ∈ Ω
//
// N_p: the 4-neighbours of p inside the target; f*: the target; g: the source
// moved by the offset; v_pq = g_p − g_q (normal, eq. 11) or, per channel, the
// larger in magnitude of f*_p − f*_q and g_p − g_q (mixed, eq. 13; the
// assignment's eq. 16).
#pragma once

#include <cstdint>

#include <opencv2/core.hpp>

namespace loom::poisson {

enum class Guidance { normal, mixed };

// Ω on a grid: `unknown` (rect-sized, 255 = in Ω) over `rect`, the region's
// bounding box in target pixels grown by the one-pixel ring ∂Ω and clipped to
// the target. Neighbours outside `rect` are outside the target, so |N_p|
// counts in-rect neighbours only.
struct BlendRegion {
  cv::Rect rect;
  cv::Mat1b unknown;
  int count = 0;                 // |Ω|
  bool clipped_target = false;   // region pixels fell outside the target
  bool clipped_source = false;   // region pixels on the source border were left out
};

// region  source-sized mask, nonzero = in Ω
// offset  source pixel (x, y) lands on target pixel (x, y) + offset
// Source-border pixels are left out of Ω (their guidance v_pq would need
// pixels outside the source); pixels landing outside the target are clipped.
// Throws loom::Error when nothing is left or Ω would cover the whole target.
BlendRegion place_region(const cv::Mat1b& region, cv::Point offset, cv::Size target);

// A stable hash of Ω's shape (rect size and mask): the matrix depends on it
// only, so it keys cached factorizations and multigrid hierarchies.
std::uint64_t region_key(const BlendRegion& r);

// The right-hand side b_p of eq. 7 for every p ∈ Ω (0 elsewhere).
//   target  target image, CV_32FC(C)     source  source image, CV_32FC(C)
// Returns a rect-sized CV_32FC(C) matrix.
cv::Mat poisson_rhs(const BlendRegion& r, const cv::Mat& target, const cv::Mat& source,
                    cv::Point offset, Guidance mode);

// The source moved by the offset, on the region's rect (0 where it has no
// source pixel): the starting guess of iterative solvers. rect-sized CV_32FC(C).
cv::Mat source_on_rect(const BlendRegion& r, const cv::Mat& source, cv::Point offset);

}  // namespace loom::poisson
