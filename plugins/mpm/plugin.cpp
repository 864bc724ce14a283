#include "loom/plugin.hpp"

LOOM_PLUGIN("mpm", "MLS-MPM continuum simulation (fluid, elastic, snow, sand; 2D and 3D) and gravitational orbits")
