#include "loom/plugin.hpp"

LOOM_PLUGIN("color", "ColorConvert, DisplayView: colour spaces and views of an OpenColorIO config")
