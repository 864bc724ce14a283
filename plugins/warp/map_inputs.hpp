// The inputs that define a warp map, shared by ImageWarp and WarpField so the
// two nodes always agree on what a graph means.
#pragma once

#include "loom/node.hpp"
#include "warp_image.hpp"

namespace loom::warp {

// pairs, method, idw_power, idw_affine, rbf_kernel, rbf_exponent, lambda.
void declare_map_inputs(NodeSpec& s);

// Which way a map goes: p_i → q_i, or q_i → p_i (evaluated per output pixel).
enum class MapDirection { forward, inverse };

// Fits the map the inputs define in the given direction. Dropped, merged or
// degenerate pairs are reported with ctx.warn.
RowMap fit_map(Inputs& in, Context& ctx, MapDirection direction);

}  // namespace loom::warp
