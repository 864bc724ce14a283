#include "mesh_codec.hpp"

#include <memory>
#include <random>

#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "loom/error.hpp"

namespace loom::io {

namespace fs = std::filesystem;

Mesh read_mesh(const fs::path& path, int* dropped) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw Error("cannot read mesh " + path.string() + ": no such file");
  Assimp::Importer importer;
  // Keep lines and points out of the triangles; count what was dropped.
  const aiScene* scene = importer.ReadFile(
      path.string(), aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                         aiProcess_PreTransformVertices | aiProcess_SortByPType);
  if (!scene || !scene->mRootNode)
    throw Error("cannot read mesh " + path.string() + ": " + importer.GetErrorString());

  Eigen::Index nv = 0, nf = 0;
  bool uv = true, normals = true, colors = true;
  int skipped = 0;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* a = scene->mMeshes[m];
    if (!(a->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) {
      skipped += static_cast<int>(a->mNumFaces);
      continue;
    }
    nv += a->mNumVertices;
    nf += a->mNumFaces;
    uv = uv && a->HasTextureCoords(0);
    normals = normals && a->HasNormals();
    colors = colors && a->HasVertexColors(0);
  }
  if (nf == 0) throw Error(path.string() + " has no triangles");
  Mesh mesh;
  mesh.V.resize(nv, 3);
  mesh.F.resize(nf, 3);
  if (uv) mesh.UV.resize(nv, 2);
  if (normals) mesh.N.resize(nv, 3);
  if (colors) mesh.C.resize(nv, 3);
  Eigen::Index v0 = 0, f0 = 0;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* a = scene->mMeshes[m];
    if (!(a->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    for (unsigned i = 0; i < a->mNumVertices; ++i) {
      const auto& p = a->mVertices[i];
      mesh.V.row(v0 + i) << p.x, p.y, p.z;
      if (uv) mesh.UV.row(v0 + i) << a->mTextureCoords[0][i].x, a->mTextureCoords[0][i].y;
      if (normals) mesh.N.row(v0 + i) << a->mNormals[i].x, a->mNormals[i].y, a->mNormals[i].z;
      if (colors) mesh.C.row(v0 + i) << a->mColors[0][i].r, a->mColors[0][i].g, a->mColors[0][i].b;
    }
    for (unsigned f = 0; f < a->mNumFaces; ++f) {
      const aiFace& face = a->mFaces[f];
      if (face.mNumIndices != 3) throw Error(path.string() + ": a face is not a triangle after triangulation");
      for (int k = 0; k < 3; ++k) mesh.F(f0 + f, k) = static_cast<int>(v0 + face.mIndices[k]);
    }
    v0 += a->mNumVertices;
    f0 += a->mNumFaces;
  }
  if (dropped) *dropped = skipped;
  require_valid(mesh, path.filename().string().c_str());
  return mesh;
}

namespace {

std::string assimp_format(const fs::path& path) {
  std::string e = path.extension().string();
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (e == ".obj") return "obj";
  if (e == ".ply") return "plyb";
  if (e == ".gltf") return "gltf2";
  if (e == ".glb") return "glb2";
  if (e == ".stl") return "stlb";
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

}  // namespace

void write_mesh(const Mesh& mesh, const fs::path& path, const std::string& texture) {
  require_valid(mesh, "the mesh");
  if (mesh.faces() == 0) throw Error("the mesh has no faces: nothing to save");
  const std::string format = assimp_format(path);
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(dir, ec);
  const fs::path staging = dir / (".loom-mesh-" + std::to_string(std::random_device{}()));
  fs::create_directories(staging, ec);
  if (ec) throw Error("cannot write " + path.string() + ": " + ec.message());
  auto scene = make_scene(mesh, texture);
  Assimp::Exporter exporter;
  const fs::path staged = staging / path.filename();
  if (exporter.Export(scene.get(), format, staged.string()) != AI_SUCCESS) {
    fs::remove_all(staging, ec);
    throw Error("cannot write " + path.string() + ": " + exporter.GetErrorString());
  }
  // The main file last, so that a reader who sees it finds its .mtl too.
  for (const auto& e : fs::directory_iterator(staging))
    if (e.path().filename() != path.filename()) fs::rename(e.path(), dir / e.path().filename(), ec);
  fs::rename(staged, path, ec);
  std::error_code ignore;
  fs::remove_all(staging, ignore);
  if (ec) throw Error("cannot write " + path.string() + ": " + ec.message());
}

}  // namespace loom::io
