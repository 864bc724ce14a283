#include "loom/plugin.hpp"

LOOM_PLUGIN("volume", "PointsToVolume (points splatted to OpenVDB grids), SaveVDB (OpenVDB files)")
