// Mesh files <-> loom::Mesh. OBJ, PLY and OFF are read and written (OFF read
// only) by Loom's own code, which keeps the file's vertex list and faces
// exactly; glTF/GLB, STL and assimp's other formats go through assimp.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include "indexed_mesh.hpp"
#include "loom/mesh.hpp"

namespace loom::io {

// All triangles of the file. OBJ, PLY, OFF: the file's vertices in the file's
// order; a vertex whose corners carry different UVs or normals is split (the
// copies appended), polygons are fan-triangulated, faces repeating a vertex
// left out (counted in notes). Other formats: each primitive's vertex list as
// assimp reads it (glTF indices kept), node transforms applied. Throws
// loom::Error naming the file for anything malformed.
Mesh read_mesh(const std::filesystem::path& path, MeshNotes* notes = nullptr);

// Writes by extension: .obj (with a .mtl beside it), .ply, .gltf, .glb, .stl.
// `texture`, when not empty, becomes the material's diffuse map. Each file is
// made in memory, then all are staged and renamed together (write_files_atomic), so a
// failing write changes no file. `check_cancelled` runs every 32768 rows while
// the bytes are made and once more before any file is touched: a cancelled
// write leaves no file and no temporary file.
void write_mesh(const Mesh& mesh, const std::filesystem::path& path, const std::string& texture,
                const std::function<void()>& check_cancelled = {});

}  // namespace loom::io
