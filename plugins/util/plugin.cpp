#include "loom/plugin.hpp"

LOOM_PLUGIN("util", "Constants, Switch, scalar math and Print: graph plumbing with no heavy dependencies")
