// Registration only: the plugin's name and one line about it. Each node
// registers itself with LOOM_NODE in its own file.
#include "loom/plugin.hpp"

LOOM_PLUGIN("example", "An example plugin to copy: Posterize")
