#include "loom/plugin.hpp"

LOOM_PLUGIN("util", "Constants, Switch, scalar math, Print and Time: graph plumbing with no heavy dependencies")
