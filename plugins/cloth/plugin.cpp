#include "loom/plugin.hpp"

LOOM_PLUGIN("cloth", "mass-spring cloth and soft bodies: implicit Euler by Newton and by local/global (Liu 2013)")
