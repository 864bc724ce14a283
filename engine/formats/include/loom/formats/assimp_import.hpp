// Reading files through assimp the way every Loom plugin does (io's LoadMesh
// and scene's LoadScene): one import policy, one conversion to Mesh, and the
// limits checked before assimp allocates anything.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>
#include <string>
#include <vector>

#include <assimp/Importer.hpp>
#include <assimp/scene.h>

#include "loom/mesh.hpp"

namespace loom::formats {

// A glTF node tree expanded into more node instances than this (a node listed
// as a child of several parents is copied per parent) is refused.
constexpr std::uint64_t kMaxSceneNodeInstances = 100'000;

// Reads `path` with aiProcess_ValidateDataStructure | Triangulate | SortByPType
// and `extra_flags`, never JoinIdenticalVertices (it welds the two sides of a
// cut). Before assimp reads anything: `path` and every file the scene refers
// to (an .mtl, a glTF buffer) must be regular files (a FIFO blocks open()
// forever); a GLB's chunks must fit in the file; a glTF's buffers may not
// claim more bytes than their source holds, and its node tree may not expand
// beyond kMaxSceneNodeInstances. Throws loom::Error naming the file.
// `opened`, when given, receives every other file assimp opened for it (an
// .mtl, a glTF's buffers): a node declares them (Context::depends_on_file).
const aiScene* import_scene(Assimp::Importer& importer, const std::filesystem::path& path,
                            unsigned extra_flags = 0, std::vector<std::filesystem::path>* opened = nullptr);

// One triangle mesh of an imported scene with its own vertex list, as assimp
// holds it (nothing joined: a cut stays cut), UVs, normals and colours where
// present, and every face's indices checked against the vertices. `what`
// names the mesh in errors.
Mesh mesh_from_assimp(const aiMesh& mesh, const std::string& what);

}  // namespace loom::formats
