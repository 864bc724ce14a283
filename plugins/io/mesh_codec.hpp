// Mesh files <-> loom::Mesh, through assimp (OBJ, PLY, glTF/GLB, STL, OFF, ...).
#pragma once

#include <filesystem>
#include <string>

#include "loom/mesh.hpp"

namespace loom::io {

// All triangles of all meshes in the file, node transforms applied, identical
// vertices joined (so OBJ corners become shared vertices); UVs, normals and
// colors kept when every part has them. Lines and points are dropped with
// `dropped` counting them.
Mesh read_mesh(const std::filesystem::path& path, int* dropped_primitives = nullptr);

// Writes by extension: .obj (with a .mtl beside it), .ply, .gltf, .glb, .stl.
// `texture`, when not empty, becomes the material's diffuse map. Each file is
// written to a temporary folder and renamed into place.
void write_mesh(const Mesh& mesh, const std::filesystem::path& path, const std::string& texture);

}  // namespace loom::io
