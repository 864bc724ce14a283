// The benchmark's scenes: Embree's cornell_box model as Embree's tutorial
// path tracer sees it, the night scene of graphs/pathtrace-night.json, and a
// ball under a map with one bright pixel.
#pragma once

#include <filesystem>

#include "loom/scene.hpp"

namespace loom::pathtrace::bench {

// cornell_box.obj + .mtl (Kd per group, Lambertian; the light quad is
// commented out in the file) with cornell_box.ecs's point light (213 300 227,
// intensity 100000) and camera (278 273 -800 looking at 278 273 0, 37°).
Scene embree_cornell_box(const std::filesystem::path& models);
// The same box with a light grey Lambertian ball of 4·rings² triangles
// resting on its floor (a scene whose rays cost Embree more traversal).
Scene embree_cornell_box_with_ball(const std::filesystem::path& models, int rings);
Scene night_scene(bool lamp);
Scene bright_pixel_scene();
// Lit by an emissive mesh: a diffuse ground, ball and box under a glowing
// sphere mesh (one-sided, 24×48 faces) and a dim uniform sky. Every mesh is
// flat shaded (no vertex normals), so Blender sees the same surfaces.
Scene emissive_mesh_scene();

}  // namespace loom::pathtrace::bench
