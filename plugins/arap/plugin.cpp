#include "loom/plugin.hpp"

LOOM_PLUGIN("arap", "ASAP and ARAP parameterization (Liu et al. 2008), prefactored local/global solver")
