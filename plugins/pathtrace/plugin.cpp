#include "loom/plugin.hpp"

LOOM_PLUGIN("pathtrace",
            "PathTrace (Embree 3): next-event estimation, MIS, environment importance sampling; "
            "CornellBox and NightSky scenes")
