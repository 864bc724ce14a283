// The inputs that define a warp map, shared by ImageWarp and WarpField so the
// two nodes always agree on what a graph means.
#pragma once

#include "loom/node.hpp"
#include "warp_image.hpp"

namespace loom::warp {

// pairs, method, idw_power, idw_affine, rbf_kernel, rbf_exponent, lambda.
void declare_map_inputs(NodeSpec& s);

// Fits the map the inputs define: p_i → q_i, or q_i → p_i when `swapped`
// (the inverse map, evaluated per output pixel). Dropped, merged or
// degenerate pairs are reported with ctx.warn.
RowMap fit_map(Inputs& in, Context& ctx, bool swapped);

}  // namespace loom::warp
