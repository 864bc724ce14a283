#include "loom/plugin.hpp"

LOOM_PLUGIN("scene", "Scene assembly for the renderers: Material, Object, Light, Camera, Environment, MergeScenes")
