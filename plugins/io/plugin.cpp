#include "loom/plugin.hpp"

LOOM_PLUGIN("io", "LoadImage, SaveImage (OpenCV), LoadMesh, SaveMesh (assimp), SavePoints (PLY point clouds), SaveJSON")
