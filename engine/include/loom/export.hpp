// Plugin author API. Symbol visibility for the engine libraries. Plugins build with hidden
// visibility, so only what is marked here crosses a shared-library boundary.
#pragma once

#define LOOM_EXPORT __attribute__((visibility("default")))
#define LOOM_API LOOM_EXPORT
