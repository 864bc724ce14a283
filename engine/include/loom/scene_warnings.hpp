// Plugin author API. What both renderers (Render and PathTrace) warn about before drawing a
// scene, so a silent black or untextured image says why.
#pragma once

#include <string>
#include <vector>

#include "loom/scene.hpp"

namespace loom {

// True when something emits light: a light of positive intensity and color,
// an object with positive emission, or an environment that is not black.
// Nothing lights a scene by default: no light, black environment.
LOOM_API bool scene_is_lit(const Scene& scene);

// The warnings a renderer gives for this scene: nothing lights it (surfaces
// would render black), and each mesh object whose material has a base-color,
// normal or displacement map but whose mesh has no UVs (the map cannot be
// placed: a base-color map shows one texel, the others do nothing). Empty
// when there is nothing to say.
LOOM_API std::vector<std::string> scene_warnings(const Scene& scene);

}  // namespace loom
