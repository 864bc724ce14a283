#include "loom/formats/assimp_import.hpp"

#include <cstring>
#include <fstream>
#include <map>
#include <optional>
#include <vector>

#include <assimp/DefaultIOSystem.h>
#include <assimp/postprocess.h>
#include <nlohmann/json.hpp>

#include "loom/error.hpp"
#include "loom/formats/mesh_file_counts.hpp"
#include "loom/input_file.hpp"

namespace loom::formats {
namespace fs = std::filesystem;

namespace {

// assimp opens every file through this: a file the scene refers to that is
// not a regular file is refused (and remembered for the message) instead of
// blocking in open().
// (DefaultIOSystem::Exists opens the file too.)
class RegularFilesOnly : public Assimp::DefaultIOSystem {
 public:
  bool Exists(const char* file) const override { return regular(file) && DefaultIOSystem::Exists(file); }
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    if (!regular(file)) return nullptr;
    opened.emplace_back(file);
    return DefaultIOSystem::Open(file, mode);
  }
  mutable std::string refused;
  std::vector<fs::path> opened;

 private:
  bool regular(const char* file) const {
    std::error_code ec;
    if (!fs::exists(file, ec)) return false;  // a missing file is assimp's to report
    try {
      require_input_file(file, "file");
      return true;
    } catch (const Error& e) {
      if (refused.empty()) refused = e.what();
      return false;
    }
  }
};

std::string read_at(std::ifstream& in, std::uint64_t offset, std::uint64_t size) {
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.seekg(static_cast<std::streamoff>(offset));
  if (!in.read(bytes.data(), static_cast<std::streamsize>(size))) throw Error("truncated");
  return bytes;
}

std::uint32_t u32(const std::string& b, std::size_t at) {
  std::uint32_t v;
  std::memcpy(&v, b.data() + at, 4);  // GLB is little-endian, as the hosts Loom runs on
  return v;
}

struct GltfParts {
  std::string json;
  std::uint64_t bin_bytes = 0;  // the GLB's BIN chunk
};

// A GLB's header and chunk headers, each length checked against the file
// before anything is read by it (glTF 2: 12-byte header, chunks of length,
// type, data; glTF 1: 20-byte header with the JSON's length).
GltfParts glb_parts(std::ifstream& in, std::uint64_t file_size, const std::string& name) {
  auto fail = [&](const std::string& why) { throw Error("cannot read " + name + ": " + why); };
  if (file_size < 20) fail("a GLB file shorter than its header");
  const std::string header = read_at(in, 0, 20);
  const std::uint32_t version = u32(header, 4), length = u32(header, 8);
  if (length > file_size)
    fail("its GLB header claims " + std::to_string(length) + " bytes, but the file has " + std::to_string(file_size));
  GltfParts parts;
  if (version == 1) {
    const std::uint32_t json_bytes = u32(header, 12);
    if (json_bytes > length - 20) fail("its GLB content claims " + std::to_string(json_bytes) + " bytes, more than the file holds");
    parts.json = read_at(in, 20, json_bytes);
    parts.bin_bytes = length - 20 - json_bytes;
    return parts;
  }
  for (std::uint64_t at = 12; at + 8 <= length;) {
    const std::string chunk = read_at(in, at, 8);
    const std::uint64_t bytes = u32(chunk, 0);
    if (bytes > length - at - 8)
      fail("a GLB chunk claims " + std::to_string(bytes) + " bytes, but only " + std::to_string(length - at - 8) +
           " follow it");
    if (std::memcmp(chunk.data() + 4, "JSON", 4) == 0 && parts.json.empty()) parts.json = read_at(in, at + 8, bytes);
    else if (std::memcmp(chunk.data() + 4, "BIN\0", 4) == 0) parts.bin_bytes = bytes;
    at += 8 + ((bytes + 3) & ~std::uint64_t(3));
  }
  return parts;
}

// Only what the limits need, nothing nested deeper than 64: parsing a hostile
// document keeps neither its bulk nor its depth.
nlohmann::json gltf_outline(const std::string& text, const std::string& name) {
  const auto keep = [&](int depth, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    if (depth > 64) throw Error("cannot read " + name + ": its JSON is nested deeper than 64");
    if (event == nlohmann::json::parse_event_t::key && depth == 1)
      return parsed == "nodes" || parsed == "scenes" || parsed == "buffers";
    return true;
  };
  nlohmann::json outline = nlohmann::json::parse(text, keep, false);
  if (outline.is_discarded() || !outline.is_object()) return nlohmann::json::object();  // assimp will say why
  return outline;
}

const nlohmann::json& member(const nlohmann::json& j, const char* key) {
  static const nlohmann::json none = nlohmann::json::array();
  if (!j.is_object()) return none;
  auto it = j.find(key);
  return it != j.end() && it->is_array() ? *it : none;
}

// How many node instances the scene's trees expand to (a node listed under
// two parents is copied twice), counted with memoized sums that stop at the
// limit; a cycle is left to assimp, which refuses it.
std::uint64_t node_instances(const nlohmann::json& gltf) {
  const nlohmann::json& nodes = member(gltf, "nodes");
  const std::uint64_t cap = kMaxSceneNodeInstances + 1;
  std::vector<std::uint64_t> count(nodes.size(), 0);
  std::vector<char> state(nodes.size(), 0);  // 0 new, 1 on the stack, 2 counted
  std::vector<std::pair<std::size_t, std::size_t>> stack;  // node, next child
  auto children = [&](std::size_t n) -> const nlohmann::json& { return member(nodes[n], "children"); };
  auto visit = [&](std::size_t root) {
    if (state[root]) return;
    state[root] = 1;
    count[root] = 1;
    stack.emplace_back(root, 0);
    while (!stack.empty()) {
      auto& [n, next] = stack.back();
      const nlohmann::json& kids = children(n);
      if (next < kids.size()) {
        const auto& k = kids[next++];
        if (!k.is_number_unsigned() || k.get<std::uint64_t>() >= nodes.size()) continue;
        const auto c = k.get<std::size_t>();
        if (state[c] == 0) {
          state[c] = 1;
          count[c] = 1;
          stack.emplace_back(c, 0);
        } else if (state[c] == 2) {
          count[n] = std::min(cap, count[n] + count[c]);
        }
        continue;
      }
      const std::size_t done = n;
      state[done] = 2;
      stack.pop_back();
      if (!stack.empty()) count[stack.back().first] = std::min(cap, count[stack.back().first] + count[done]);
    }
  };
  std::uint64_t total = 0;
  const nlohmann::json& scenes = member(gltf, "scenes");
  for (const auto& scene : scenes)
    for (const auto& r : member(scene, "nodes"))
      if (r.is_number_unsigned() && r.get<std::uint64_t>() < nodes.size()) {
        visit(r.get<std::size_t>());
        total = std::min(cap, total + count[r.get<std::size_t>()]);
      }
  if (!scenes.empty()) return total;
  std::vector<char> has_parent(nodes.size(), 0);  // no scene: every node without a parent is a root
  for (std::size_t n = 0; n < nodes.size(); ++n)
    for (const auto& k : children(n))
      if (k.is_number_unsigned() && k.get<std::uint64_t>() < nodes.size()) has_parent[k.get<std::size_t>()] = 1;
  for (std::size_t n = 0; n < nodes.size(); ++n)
    if (!has_parent[n]) {
      visit(n);
      total = std::min(cap, total + count[n]);
    }
  return total;
}

// A buffer may not claim more bytes than its source holds: the GLB's BIN
// chunk, a data URI's decoded bytes, or a file beside the scene.
void check_buffers(const nlohmann::json& gltf, const GltfParts& parts, const fs::path& path) {
  for (const auto& b : member(gltf, "buffers")) {
    if (!b.is_object() || !b.contains("byteLength") || !b["byteLength"].is_number()) continue;
    const double claimed = b["byteLength"].get<double>();
    double available = static_cast<double>(parts.bin_bytes);
    if (b.contains("uri") && b["uri"].is_string()) {
      const std::string uri = b["uri"].get<std::string>();
      if (uri.rfind("data:", 0) == 0) {
        available = static_cast<double>(uri.size()) * 3 / 4;
      } else {
        const fs::path file = path.parent_path() / uri;
        require_input_file(file, "the buffer of " + path.string() + ",");
        std::error_code ec;
        available = static_cast<double>(fs::file_size(file, ec));
      }
    }
    if (claimed > available)
      throw Error("cannot read " + path.string() + ": a buffer claims " + std::to_string(static_cast<std::uint64_t>(claimed)) +
                  " bytes, but its source holds " + std::to_string(static_cast<std::uint64_t>(available)));
  }
}

void check_gltf(const fs::path& path) {
  std::error_code ec;
  const std::uint64_t size = fs::file_size(path, ec);
  std::ifstream in(path, std::ios::binary);
  if (ec || !in) return;  // assimp reports it
  char magic[4] = {};
  in.read(magic, 4);
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  GltfParts parts;
  const std::string name = path.string();
  if (in && std::memcmp(magic, "glTF", 4) == 0) {
    parts = glb_parts(in, size, name);
  } else if (ext == ".gltf") {
    parts.json = read_at(in, 0, size);
  } else {
    return;
  }
  const nlohmann::json gltf = gltf_outline(parts.json, name);
  if (node_instances(gltf) > kMaxSceneNodeInstances)
    throw Error("cannot read " + name + ": its node tree expands to more than " +
                std::to_string(kMaxSceneNodeInstances) + " node instances (nodes listed as children of several parents)");
  check_buffers(gltf, parts, path);
}

}  // namespace

const aiScene* import_scene(Assimp::Importer& importer, const fs::path& path, unsigned extra_flags,
                            std::vector<fs::path>* opened) {
  require_input_file(path, "scene");
  check_gltf(path);
  check_declared_counts(path);  // OFF/PLY/X headers: before assimp allocates what they claim
  std::error_code ec;
  auto* io = new RegularFilesOnly;
  importer.SetIOHandler(io);  // the importer owns it
  const aiScene* scene = importer.ReadFile(
      path.string(), aiProcess_ValidateDataStructure | aiProcess_Triangulate | aiProcess_SortByPType | extra_flags);
  if (opened)
    for (const fs::path& f : io->opened)
      if (!fs::equivalent(f, path, ec)) opened->push_back(f);
  if (!io->refused.empty()) throw Error("cannot read scene " + path.string() + ": " + io->refused);
  if (!scene || !scene->mRootNode) throw Error("cannot read " + path.string() + ": " + importer.GetErrorString());
  return scene;
}

Mesh mesh_from_assimp(const aiMesh& a, const std::string& what) {
  Mesh m;
  const Eigen::Index n = a.mNumVertices;
  m.V.resize(n, 3);
  if (a.HasNormals()) m.N.resize(n, 3);
  if (a.HasTextureCoords(0)) m.UV.resize(n, 2);
  if (a.HasVertexColors(0)) m.C.resize(n, 3);
  for (Eigen::Index v = 0; v < n; ++v) {
    m.V.row(v) << a.mVertices[v].x, a.mVertices[v].y, a.mVertices[v].z;
    if (a.HasNormals()) m.N.row(v) << a.mNormals[v].x, a.mNormals[v].y, a.mNormals[v].z;
    if (a.HasTextureCoords(0)) m.UV.row(v) << a.mTextureCoords[0][v].x, a.mTextureCoords[0][v].y;
    if (a.HasVertexColors(0)) m.C.row(v) << a.mColors[0][v].r, a.mColors[0][v].g, a.mColors[0][v].b;
  }
  m.F.resize(a.mNumFaces, 3);
  for (unsigned f = 0; f < a.mNumFaces; ++f) {
    const aiFace& face = a.mFaces[f];
    if (face.mNumIndices != 3) throw Error(what + ": a face is not a triangle after triangulation");
    for (int k = 0; k < 3; ++k) {
      if (face.mIndices[k] >= a.mNumVertices) throw Error(what + ": a face index is out of range");
      m.F(f, k) = static_cast<int>(face.mIndices[k]);
    }
  }
  return m;
}

}  // namespace loom::formats
