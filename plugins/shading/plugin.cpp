#include "loom/plugin.hpp"

LOOM_PLUGIN("shading", "headless OpenGL rendering (OSMesa): Blinn-Phong, normal and displacement "
                       "mapping, shadow maps with PCF/PCSS; mesh denoising by a displacement map")
