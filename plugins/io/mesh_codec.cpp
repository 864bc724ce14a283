#include "mesh_codec.hpp"

#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>

#include <assimp/Exporter.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "loom/atomic_file.hpp"
#include "loom/error.hpp"
#include "loom/formats/assimp_import.hpp"
#include "loom/input_file.hpp"

namespace loom::io {

namespace fs = std::filesystem;

namespace {

std::string lower_extension(const fs::path& path) {
  std::string e = path.extension().string();
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

// Formats without indices of their own (STL) or with several meshes (glTF,
// FBX, ...) through assimp (loom/formats/assimp_import.hpp: nothing joined,
// indices checked), each primitive's vertex list as it is, one after another.
// UVs, normals and colors are kept when every primitive has them.
Mesh read_with_assimp(const fs::path& path, MeshNotes& notes) {
  Assimp::Importer importer;
  const aiScene* scene = formats::import_scene(importer, path, aiProcess_PreTransformVertices);
  std::vector<Mesh> parts;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* a = scene->mMeshes[m];
    if (!(a->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) {
      notes.dropped_primitives += static_cast<int>(a->mNumFaces);
      continue;
    }
    parts.push_back(formats::mesh_from_assimp(*a, path.string()));
  }
  Eigen::Index nv = 0, nf = 0;
  bool uv = true, normals = true, colors = true;
  for (const Mesh& p : parts) {
    nv += p.vertices();
    nf += p.faces();
    uv = uv && p.has_uv();
    normals = normals && p.has_normals();
    colors = colors && p.has_colors();
  }
  if (nf == 0) throw Error(path.string() + " has no triangles");
  Mesh mesh;
  mesh.V.resize(nv, 3);
  mesh.F.resize(nf, 3);
  if (uv) mesh.UV.resize(nv, 2);
  if (normals) mesh.N.resize(nv, 3);
  if (colors) mesh.C.resize(nv, 3);
  Eigen::Index v0 = 0, f0 = 0;
  for (const Mesh& p : parts) {
    mesh.V.middleRows(v0, p.vertices()) = p.V;
    if (uv) mesh.UV.middleRows(v0, p.vertices()) = p.UV;
    if (normals) mesh.N.middleRows(v0, p.vertices()) = p.N;
    if (colors) mesh.C.middleRows(v0, p.vertices()) = p.C;
    mesh.F.middleRows(f0, p.faces()) = p.F.array() + static_cast<int>(v0);
    v0 += p.vertices();
    f0 += p.faces();
  }
  return mesh;
}

// Whole file in memory; a mesh file beyond this is refused, not read.
constexpr std::uintmax_t kMaxMeshFileBytes = std::uintmax_t(4) << 30;

std::string file_bytes(const fs::path& path) {
  std::error_code ec;
  const auto size = fs::file_size(path, ec);
  if (ec) throw Error("cannot read mesh " + path.string() + ": " + ec.message());
  if (size > kMaxMeshFileBytes) throw Error("cannot read mesh " + path.string() + ": larger than 4 GiB");
  std::ifstream in(path, std::ios::binary);
  std::string bytes(static_cast<std::size_t>(size), '\0');
  if (!in.read(bytes.data(), static_cast<std::streamsize>(size)))
    throw Error("cannot read mesh " + path.string() + ": read failed");
  return bytes;
}

void require_finite_attributes(const Mesh& mesh, const std::string& what) {
  if (!mesh.UV.allFinite() || !mesh.N.allFinite() || !mesh.C.allFinite())
    throw Error(what + " has NaN or infinite texture coordinates, normals or colors");
}

}  // namespace

Mesh read_mesh(const fs::path& path, MeshNotes* notes) {
  require_input_file(path, "mesh");
  MeshNotes local;
  MeshNotes& n = notes ? *notes : local;
  const std::string ext = lower_extension(path), name = path.string();
  Mesh mesh;
  if (ext == ".obj") mesh = to_mesh(read_obj_file(file_bytes(path), name), name, &n);
  else if (ext == ".ply") mesh = to_mesh(read_ply_file(file_bytes(path), name), name, &n);
  else if (ext == ".off") mesh = to_mesh(read_off_file(file_bytes(path), name), name, &n);
  else mesh = read_with_assimp(path, n);
  require_valid(mesh, name.c_str());
  require_finite_attributes(mesh, name);
  return mesh;
}

namespace {

std::string assimp_format(const std::string& ext, const fs::path& path) {
  if (ext == ".gltf") return "gltf2";
  if (ext == ".glb") return "glb2";
  if (ext == ".stl") return "stlb";
  throw Error("cannot save " + path.string() + ": unknown extension (use .obj, .ply, .gltf, .glb or .stl)");
}

// An aiScene of one mesh and one material. aiScene's destructor frees what
// is attached to it.
std::unique_ptr<aiScene> make_scene(const Mesh& mesh, const std::string& texture) {
  auto scene = std::make_unique<aiScene>();
  scene->mRootNode = new aiNode("root");
  scene->mRootNode->mNumMeshes = 1;
  scene->mRootNode->mMeshes = new unsigned[1]{0};
  scene->mNumMaterials = 1;
  scene->mMaterials = new aiMaterial*[1];
  auto* material = new aiMaterial();
  aiString material_name("loom");
  material->AddProperty(&material_name, AI_MATKEY_NAME);
  aiColor3D white(1, 1, 1);
  material->AddProperty(&white, 1, AI_MATKEY_COLOR_DIFFUSE);
  if (!texture.empty()) {
    aiString file(texture);
    material->AddProperty(&file, AI_MATKEY_TEXTURE_DIFFUSE(0));
  }
  scene->mMaterials[0] = material;

  auto* m = new aiMesh();
  scene->mNumMeshes = 1;
  scene->mMeshes = new aiMesh*[1]{m};
  m->mMaterialIndex = 0;
  m->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  const unsigned nv = static_cast<unsigned>(mesh.vertices());
  m->mNumVertices = nv;
  m->mVertices = new aiVector3D[nv];
  for (unsigned i = 0; i < nv; ++i)
    m->mVertices[i] = aiVector3D(static_cast<float>(mesh.V(i, 0)), static_cast<float>(mesh.V(i, 1)),
                                 static_cast<float>(mesh.V(i, 2)));
  if (mesh.has_uv()) {
    m->mTextureCoords[0] = new aiVector3D[nv];
    m->mNumUVComponents[0] = 2;
    for (unsigned i = 0; i < nv; ++i)
      m->mTextureCoords[0][i] = aiVector3D(static_cast<float>(mesh.UV(i, 0)), static_cast<float>(mesh.UV(i, 1)), 0);
  }
  if (mesh.has_normals()) {
    m->mNormals = new aiVector3D[nv];
    for (unsigned i = 0; i < nv; ++i)
      m->mNormals[i] = aiVector3D(static_cast<float>(mesh.N(i, 0)), static_cast<float>(mesh.N(i, 1)),
                                  static_cast<float>(mesh.N(i, 2)));
  }
  if (mesh.has_colors()) {
    m->mColors[0] = new aiColor4D[nv];
    for (unsigned i = 0; i < nv; ++i)
      m->mColors[0][i] = aiColor4D(static_cast<float>(mesh.C(i, 0)), static_cast<float>(mesh.C(i, 1)),
                                   static_cast<float>(mesh.C(i, 2)), 1);
  }
  const unsigned nf = static_cast<unsigned>(mesh.faces());
  m->mNumFaces = nf;
  m->mFaces = new aiFace[nf];
  for (unsigned f = 0; f < nf; ++f) {
    m->mFaces[f].mNumIndices = 3;
    m->mFaces[f].mIndices = new unsigned[3];
    for (int k = 0; k < 3; ++k) m->mFaces[f].mIndices[k] = static_cast<unsigned>(mesh.F(f, k));
  }
  return scene;
}

// "%.17g": doubles survive the text round trip exactly.
void append_numbers(std::string& out, const char* tag, const double* x, int n) {
  char buffer[40];
  out += tag;
  for (int i = 0; i < n; ++i) {
    std::snprintf(buffer, sizeof buffer, " %.17g", x[i]);
    out += buffer;
  }
  out += '\n';
}

// OBJ keeps the vertex list as it is: one v (and vt, vn) per vertex, faces
// indexing them all with the same number. (assimp's exporter joins vertices
// by position, which would weld a cut shut.)
// Calls `check` (the node's cancellation check) once per chunk of rows, so
// that Ctrl-C acts within a chunk while a large mesh is formatted.
void every_chunk(int row, const std::function<void()>& check) {
  constexpr int chunk = 1 << 15;
  if (check && row % chunk == 0) check();
}

std::string obj_text(const Mesh& mesh, const std::string& mtl_name, const std::function<void()>& check) {
  std::string out = "# written by Loom\n";
  if (!mtl_name.empty()) out += "mtllib " + mtl_name + "\nusemtl loom\n";
  for (int v = 0; v < mesh.vertices(); ++v) {
    every_chunk(v, check);
    double x[6] = {mesh.V(v, 0), mesh.V(v, 1), mesh.V(v, 2), 0, 0, 0};
    if (mesh.has_colors())
      for (int k = 0; k < 3; ++k) x[3 + k] = mesh.C(v, k);
    append_numbers(out, "v", x, mesh.has_colors() ? 6 : 3);
  }
  for (int v = 0; mesh.has_uv() && v < mesh.vertices(); ++v) {
    every_chunk(v, check);
    const double x[2] = {mesh.UV(v, 0), mesh.UV(v, 1)};
    append_numbers(out, "vt", x, 2);
  }
  for (int v = 0; mesh.has_normals() && v < mesh.vertices(); ++v) {
    every_chunk(v, check);
    const double x[3] = {mesh.N(v, 0), mesh.N(v, 1), mesh.N(v, 2)};
    append_numbers(out, "vn", x, 3);
  }
  for (int f = 0; f < mesh.faces(); ++f) {
    every_chunk(f, check);
    out += 'f';
    for (int k = 0; k < 3; ++k) {
      const std::string i = std::to_string(mesh.F(f, k) + 1);
      out += ' ' + i;
      if (mesh.has_uv() || mesh.has_normals()) out += '/' + (mesh.has_uv() ? i : std::string());
      if (mesh.has_normals()) out += '/' + i;
    }
    out += '\n';
  }
  return out;
}

// Binary little-endian PLY with double positions, float normals, UVs and
// colors, and int face indices.
std::string ply_bytes(const Mesh& mesh, const std::function<void()>& check) {
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment written by Loom\nelement vertex " +
                    std::to_string(mesh.vertices()) + "\nproperty double x\nproperty double y\nproperty double z\n";
  if (mesh.has_normals()) out += "property float nx\nproperty float ny\nproperty float nz\n";
  if (mesh.has_uv()) out += "property float u\nproperty float v\n";
  if (mesh.has_colors()) out += "property float red\nproperty float green\nproperty float blue\n";
  out += "element face " + std::to_string(mesh.faces()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  auto put = [&out](auto value) {  // the host is little-endian (x86-64, aarch64)
    char b[sizeof value];
    std::memcpy(b, &value, sizeof value);
    out.append(b, sizeof value);
  };
  for (int v = 0; v < mesh.vertices(); ++v) {
    every_chunk(v, check);
    for (int k = 0; k < 3; ++k) put(mesh.V(v, k));
    for (int k = 0; mesh.has_normals() && k < 3; ++k) put(static_cast<float>(mesh.N(v, k)));
    for (int k = 0; mesh.has_uv() && k < 2; ++k) put(static_cast<float>(mesh.UV(v, k)));
    for (int k = 0; mesh.has_colors() && k < 3; ++k) put(static_cast<float>(mesh.C(v, k)));
  }
  for (int f = 0; f < mesh.faces(); ++f) {
    every_chunk(f, check);
    put(static_cast<unsigned char>(3));
    for (int k = 0; k < 3; ++k) put(static_cast<std::int32_t>(mesh.F(f, k)));
  }
  return out;
}

// A texture file name goes into a line of the .mtl or a JSON string: no
// line breaks or other control characters.
void require_plain_name(const std::string& texture) {
  for (unsigned char c : texture)
    if (c < 0x20 || c == 0x7f)
      throw Error("texture \"" + texture.substr(0, 60) + "\": control characters (line breaks) are not allowed in a file name");
}

}  // namespace

void write_mesh(const Mesh& mesh, const fs::path& path, const std::string& texture,
                const std::function<void()>& check_cancelled) {
  require_valid(mesh, "the mesh");
  require_finite_attributes(mesh, "the mesh");
  if (mesh.faces() == 0) throw Error("the mesh has no faces: nothing to save");
  require_plain_name(texture);
  const std::string ext = lower_extension(path);
  // Every file's bytes are made in memory first: nothing on disk changes
  // until the whole write is known to succeed.
  std::vector<std::pair<fs::path, std::string>> files;  // the main file last
  if (ext == ".obj") {
    const std::string mtl = path.stem().string() + ".mtl";
    std::string material = "# written by Loom\nnewmtl loom\nKd 1 1 1\n";
    if (!texture.empty()) material += "map_Kd " + texture + "\n";
    files.emplace_back(path.parent_path() / mtl, material);
    files.emplace_back(path, obj_text(mesh, mtl, check_cancelled));
  } else if (ext == ".ply") {
    files.emplace_back(path, ply_bytes(mesh, check_cancelled));
  } else {
    const std::string format = assimp_format(ext, path);
    auto scene = make_scene(mesh, texture);
    Assimp::Exporter exporter;
    const aiExportDataBlob* blob = exporter.ExportToBlob(scene.get(), format);
    if (!blob) throw Error("cannot write " + path.string() + ": " + exporter.GetErrorString());
    // The first blob is the main file; the others (a glTF's .bin) are named
    // after it with their own extension.
    std::string main_bytes(static_cast<const char*>(blob->data), blob->size);
    for (const aiExportDataBlob* b = blob->next; b; b = b->next) {
      std::string name = path.stem().string() + "." + std::string(b->name.C_Str());
      // In memory assimp calls the main file "$blobfile"; point the glTF's
      // buffer reference at the real name.
      const std::string placeholder = "$blobfile." + std::string(b->name.C_Str());
      for (auto at = main_bytes.find(placeholder); at != std::string::npos; at = main_bytes.find(placeholder, at))
        main_bytes.replace(at, placeholder.size(), name);
      files.emplace_back(path.parent_path() / name, std::string(static_cast<const char*>(b->data), b->size));
    }
    files.emplace_back(path, std::move(main_bytes));
  }
  // One check between files as well; a cancelled write has written nothing.
  if (check_cancelled) check_cancelled();
  write_files_atomic(files);
}

}  // namespace loom::io
