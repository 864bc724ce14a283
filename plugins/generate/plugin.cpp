#include "loom/plugin.hpp"

LOOM_PLUGIN("generate", "Demo data with no files: Checkerboard image, grid, disk, hemisphere and sphere meshes")
