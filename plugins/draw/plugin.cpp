#include "loom/plugin.hpp"

LOOM_PLUGIN("draw", "DrawShapes and PolygonMask: anti-aliased figures and polygon masks (MiniDraw assignment)")
