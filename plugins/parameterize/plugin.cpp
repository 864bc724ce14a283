#include "loom/plugin.hpp"

LOOM_PLUGIN("parameterize", "MinimalSurface, Parameterize (Tutte, harmonic, mean-value, shape-preserving), UV layout and checker pictures")
