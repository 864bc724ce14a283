#include "loom/plugin.hpp"

LOOM_PLUGIN("poisson", "PoissonBlend: seamless cloning (Pérez et al. 2003), multigrid-fast and CHOLMOD-exact")
