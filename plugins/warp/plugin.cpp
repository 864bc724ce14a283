#include "loom/plugin.hpp"

LOOM_PLUGIN("warp", "ImageWarp and WarpField: image warping by IDW and RBF (ImageWarping assignment)")
