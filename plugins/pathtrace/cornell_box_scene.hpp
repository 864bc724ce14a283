// The Cornell box (Cornell University Program of Computer Graphics' measured
// data: walls, light and the two blocks in millimetres), with the colours most
// renderers use for it (Mitsuba's and pbrt's scenes: white 0.725 0.71 0.68,
// red 0.63 0.065 0.05, green 0.14 0.45 0.091, light radiance 17 12 4) and the
// original camera: eye (278, 273, -800) looking along +z, 39.3° vertical field.
#pragma once

#include "loom/scene.hpp"

namespace loom::pathtrace {

enum class CornellContents { blocks, spheres, empty };

struct CornellBoxOptions {
  CornellContents contents = CornellContents::blocks;
  Eigen::Vector3d light_radiance{17, 12, 4};
  Eigen::Vector3d white{0.725, 0.71, 0.68}, red{0.63, 0.065, 0.05}, green{0.14, 0.45, 0.091};
};

// Walls and the light face into the box, the blocks outwards; the light is a
// one-sided emitter facing down. Spheres (a mirror and a glass ball) are
// meshes with vertex normals.
Scene cornell_box(const CornellBoxOptions& options);

}  // namespace loom::pathtrace
