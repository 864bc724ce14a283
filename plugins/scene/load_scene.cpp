// LoadScene: a whole scene file (OBJ+MTL, glTF/GLB, and what else assimp
// reads) as a Scene: every mesh with its node's transform and its material
// (base color and map, normal map, bump/height map as displacement,
// roughness, metallic -> conductor, transmission -> dielectric, emission),
// and the file's lights and first camera.
#include <assimp/GltfMaterial.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "loom/formats/assimp_import.hpp"
#include "loom/formats/image_header.hpp"
#include "loom/input_file.hpp"
#include "loom/image.hpp"
#include "loom/input_file.hpp"
#include "loom/plugin.hpp"
#include "loom/scene.hpp"

namespace {

namespace fs = std::filesystem;

Eigen::Matrix4d to_eigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d e;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) e(r, c) = m[r][c];
  return e;
}

// Reads a texture referenced by a material: embedded ("*0" or by name) or a
// file beside the scene. 8/16-bit color maps are sRGB-decoded to linear,
// data maps (normals, heights) keep their [0, 1] values.
class Textures {
 public:
  Textures(const aiScene* scene, fs::path folder) : scene_(scene), folder_(std::move(folder)) {}

  std::shared_ptr<const loom::Image> get(const aiMaterial* m, std::initializer_list<aiTextureType> types,
                                         bool color, loom::Context& ctx) {
    aiString path;
    bool found = false;
    for (aiTextureType t : types)
      if (m->GetTextureCount(t) > 0 && m->GetTexture(t, 0, &path) == AI_SUCCESS) {
        found = true;
        break;
      }
    if (!found) return nullptr;
    const std::string key = std::string(path.C_Str()) + (color ? "#color" : "#data");
    auto it = cache_.find(key);
    if (it != cache_.end()) return it->second;
    cv::Mat raw;
    try {
      raw = decode(path.C_Str());
    } catch (const loom::Error& e) {
      ctx.warn(std::string(e.what()) + ": the material goes without it");
      return cache_[key] = nullptr;
    } catch (const cv::Exception& e) {
      ctx.warn(std::string("texture ") + path.C_Str() + " could not be decoded (" + e.what() +
               "): the material goes without it");
      return cache_[key] = nullptr;
    }
    if (raw.empty()) {
      ctx.warn(std::string("texture ") + path.C_Str() + " could not be read: the material goes without it");
      return cache_[key] = nullptr;
    }
    cv::Mat rgb;
    const int ch = raw.channels();
    if (ch == 3)
      cv::cvtColor(raw, rgb, cv::COLOR_BGR2RGB);
    else if (ch == 4)
      cv::cvtColor(raw, rgb, cv::COLOR_BGRA2RGBA);
    else
      rgb = raw;
    const double scale = raw.depth() == CV_8U ? 1 / 255.0 : raw.depth() == CV_16U ? 1 / 65535.0 : 1.0;
    cv::Mat f;
    rgb.convertTo(f, CV_32F, scale);
    loom::Image image(f, color && raw.depth() != CV_32F ? loom::Encoding::srgb : loom::Encoding::linear);
    if (image.encoding == loom::Encoding::srgb) image = loom::with_encoding(image, loom::Encoding::linear);
    return cache_[key] = std::make_shared<const loom::Image>(std::move(image));
  }

  // The texture files looked for, read or not: the node's result depends on them.
  const std::vector<fs::path>& files() const { return files_; }

 private:
  // The texture's pixels as OpenCV decodes them, after its header's size is
  // checked against the pixel limit (a small file may declare a huge image)
  // and, for a file, after it is known to be a regular one (a FIFO blocks).
  cv::Mat decode(const std::string& name) const {
    const std::string limit = "LoadScene's texture limit";
    if (const aiTexture* embedded = scene_->GetEmbeddedTexture(name.c_str())) {
      if (embedded->mHeight == 0) {
        const std::string_view bytes(reinterpret_cast<const char*>(embedded->pcData), embedded->mWidth);
        loom::formats::require_declared_pixels_within(bytes, "texture " + name, loom::formats::kDefaultMaxImagePixels, limit);
        return cv::imdecode(cv::Mat(1, static_cast<int>(bytes.size()), CV_8UC1, embedded->pcData), cv::IMREAD_UNCHANGED);
      }
      if (std::uint64_t(embedded->mWidth) * embedded->mHeight > loom::formats::kDefaultMaxImagePixels)
        throw loom::Error("texture " + name + " has more pixels than the limit of " +
                          std::to_string(loom::formats::kDefaultMaxImagePixels));
      const cv::Mat bgra(static_cast<int>(embedded->mHeight), static_cast<int>(embedded->mWidth), CV_8UC4,
                         embedded->pcData);  // aiTexel is b, g, r, a
      return bgra.clone();
    }
    const fs::path file = folder_ / fs::path(name);
    files_.push_back(file);
    loom::require_input_file(file, "texture");
    std::string head(kHeaderBytes, '\0');
    std::ifstream in(file, std::ios::binary);
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<std::size_t>(in.gcount()));
    loom::formats::require_declared_pixels_within(head, "texture " + file.string(), loom::formats::kDefaultMaxImagePixels,
                                                  limit);
    return cv::imread(file.string(), cv::IMREAD_UNCHANGED);
  }

  static constexpr std::size_t kHeaderBytes = 1 << 18;  // enough for every header Loom reads but a late TIFF IFD
  const aiScene* scene_;
  fs::path folder_;
  std::map<std::string, std::shared_ptr<const loom::Image>> cache_;
  mutable std::vector<fs::path> files_;
};

loom::Material material_of(const aiMaterial* m, Textures& textures, double bump_scale, loom::Context& ctx) {
  loom::Material out;
  aiColor4D c;
  if (m->Get(AI_MATKEY_BASE_COLOR, c) == AI_SUCCESS || m->Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS)
    out.base_color = {c.r, c.g, c.b};
  aiColor3D e;
  if (m->Get(AI_MATKEY_COLOR_EMISSIVE, e) == AI_SUCCESS) out.emission = {e.r, e.g, e.b};
  float strength = 1;
  if (m->Get(AI_MATKEY_EMISSIVE_INTENSITY, strength) == AI_SUCCESS) out.emission *= strength;
  float roughness = 0, shininess = 0, metallic = 0, transmission = 0, ior = 0, specular = 0;
  if (m->Get(AI_MATKEY_ROUGHNESS_FACTOR, roughness) == AI_SUCCESS) {
    out.roughness = std::clamp<double>(roughness, 0, 1);
  } else if (m->Get(AI_MATKEY_SHININESS, shininess) == AI_SUCCESS && shininess > 0) {
    // Phong exponent s ~ 2 / alpha^2 - 2 with alpha = roughness^2.
    out.roughness = std::clamp(std::pow(2.0 / (shininess + 2.0), 0.25), 0.0, 1.0);
  }
  if (m->Get(AI_MATKEY_COLOR_SPECULAR, e) == AI_SUCCESS) specular = std::max({e.r, e.g, e.b});
  if (specular > 0) out.specular = std::clamp<double>(specular, 0, 1);
  if (m->Get(AI_MATKEY_REFRACTI, ior) == AI_SUCCESS && ior >= 1) out.ior = ior;
  if (m->Get(AI_MATKEY_METALLIC_FACTOR, metallic) == AI_SUCCESS && metallic > 0.5)
    out.model = loom::Material::Model::conductor;
  if (m->Get(AI_MATKEY_TRANSMISSION_FACTOR, transmission) == AI_SUCCESS && transmission > 0.5)
    out.model = loom::Material::Model::dielectric;
  out.base_color_map = textures.get(m, {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE}, true, ctx);
  if (out.base_color_map) out.base_color = {1, 1, 1};
  out.normal_map = textures.get(m, {aiTextureType_NORMALS}, false, ctx);
  // OBJ's map_Bump arrives as a height map: displacement along the normal.
  out.displacement_map = textures.get(m, {aiTextureType_HEIGHT, aiTextureType_DISPLACEMENT}, false, ctx);
  if (out.displacement_map) out.displacement_scale = bump_scale;
  out.base_color = out.base_color.cwiseMax(0);
  out.emission = out.emission.cwiseMax(0);
  return out;
}

// Every triangle mesh of the file by assimp's index (null for the others),
// each with its own vertex list (io's policy: a cut stays cut).
std::vector<std::shared_ptr<const loom::Mesh>> triangle_meshes(const aiScene& ai) {
  std::vector<std::shared_ptr<const loom::Mesh>> meshes(ai.mNumMeshes);
  for (unsigned i = 0; i < ai.mNumMeshes; ++i) {
    const aiMesh* a = ai.mMeshes[i];
    if (!(a->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || a->mNumFaces == 0) continue;
    auto m = std::make_shared<loom::Mesh>(loom::formats::mesh_from_assimp(*a, a->mName.C_Str()));
    if (m->has_normals() && !m->N.allFinite()) m->N.resize(0, 3);
    loom::require_valid(*m, a->mName.C_Str());
    meshes[i] = std::move(m);
  }
  return meshes;
}

// Depth-first over the node tree, accumulating transforms: one object per
// (node, triangle mesh). Returns every node's world transform by name.
std::map<std::string, Eigen::Matrix4d> place_objects(const aiScene& ai,
                                                     const std::vector<std::shared_ptr<const loom::Mesh>>& meshes,
                                                     const std::vector<loom::Material>& materials, loom::Scene& scene) {
  std::map<std::string, Eigen::Matrix4d> transforms;
  std::vector<std::pair<const aiNode*, Eigen::Matrix4d>> stack{{ai.mRootNode, Eigen::Matrix4d::Identity()}};
  while (!stack.empty()) {
    auto [node, parent] = stack.back();
    stack.pop_back();
    const Eigen::Matrix4d world = parent * to_eigen(node->mTransformation);
    transforms[node->mName.C_Str()] = world;
    for (unsigned k = 0; k < node->mNumMeshes; ++k) {
      const unsigned index = node->mMeshes[k];
      if (!meshes[index]) continue;
      loom::SceneObject o;
      o.name = node->mName.length ? node->mName.C_Str() : ai.mMeshes[index]->mName.C_Str();
      o.mesh = meshes[index];
      o.material = materials.at(ai.mMeshes[index]->mMaterialIndex);
      o.transform = world;
      scene.objects.push_back(std::move(o));
    }
    for (unsigned c = 0; c < node->mNumChildren; ++c) stack.emplace_back(node->mChildren[c], world);
  }
  return transforms;
}

// A point, spot or directional light placed by its node's transform T.
std::optional<loom::Light> light_of(const aiLight& a, const Eigen::Matrix4d& T, loom::Context& ctx) {
  loom::Light l;
  if (a.mType == aiLightSource_POINT)
    l.kind = loom::Light::Kind::point;
  else if (a.mType == aiLightSource_SPOT)
    l.kind = loom::Light::Kind::spot;
  else if (a.mType == aiLightSource_DIRECTIONAL)
    l.kind = loom::Light::Kind::directional;
  else {
    ctx.warn(std::string("light ") + a.mName.C_Str() + " is of a kind Loom does not draw: skipped");
    return std::nullopt;
  }
  l.position = (T * Eigen::Vector4d(a.mPosition.x, a.mPosition.y, a.mPosition.z, 1)).head<3>();
  Eigen::Vector3d d = T.topLeftCorner<3, 3>() * Eigen::Vector3d(a.mDirection.x, a.mDirection.y, a.mDirection.z);
  if (d.norm() > 0) l.direction = d.normalized();
  const Eigen::Vector3d color(a.mColorDiffuse.r, a.mColorDiffuse.g, a.mColorDiffuse.b);
  l.intensity = std::max(color.maxCoeff(), 0.0);
  l.color = l.intensity > 0 ? Eigen::Vector3d(color / l.intensity) : Eigen::Vector3d(1, 1, 1);
  if (l.kind == loom::Light::Kind::spot) {
    l.spot_outer = std::clamp<double>(a.mAngleOuterCone, 1e-3, 3.1);
    l.spot_inner = std::clamp<double>(a.mAngleInnerCone, 0, l.spot_outer);
  }
  return l;
}

// The file's camera placed by its node's transform T; none when its look or
// up direction is zero.
std::optional<loom::Camera> camera_of(const aiCamera& a, const Eigen::Matrix4d& T) {
  const Eigen::Vector3d eye = (T * Eigen::Vector4d(a.mPosition.x, a.mPosition.y, a.mPosition.z, 1)).head<3>();
  const Eigen::Vector3d look = T.topLeftCorner<3, 3>() * Eigen::Vector3d(a.mLookAt.x, a.mLookAt.y, a.mLookAt.z);
  const Eigen::Vector3d up = T.topLeftCorner<3, 3>() * Eigen::Vector3d(a.mUp.x, a.mUp.y, a.mUp.z);
  if (!(look.norm() > 0 && up.norm() > 0)) return std::nullopt;
  loom::Camera c;
  c.eye = eye;
  c.target = eye + look.normalized();
  c.up = up.normalized();
  // assimp gives the horizontal half angle; Loom's camera the vertical full one.
  const double aspect = a.mAspect > 0 ? a.mAspect : 1.0;
  if (a.mHorizontalFOV > 0) c.fov_y = 2 * std::atan(std::tan(a.mHorizontalFOV) / aspect);
  if (a.mClipPlaneNear > 0) c.near_plane = a.mClipPlaneNear;
  if (a.mClipPlaneFar > c.near_plane) c.far_plane = a.mClipPlaneFar;
  return c;
}

struct LoadScene {
  static constexpr const char* name = "LoadScene";
  static void declare(loom::NodeSpec& s) {
    s.describe("Reads a scene file through assimp (OBJ+MTL, glTF/GLB, FBX, ...): every triangle mesh "
               "with its node transform and material (base color and texture, normal map, bump map as "
               "displacement, roughness, metallic as conductor, transmission as dielectric, emission), "
               "the file's point/spot/directional lights and its first camera.")
        .input<std::string>("path", "the scene file").input_file()
        .input<double>("bump_scale", 0.0,
                       "displacement scale (scene units) given to materials with a bump/height map")
        .output<loom::Scene>("scene", "the scene");
  }

  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    const fs::path path = in.get<std::string>("path");
    loom::require_input_file(path, "scene", ctx.graph_dir());
    Assimp::Importer importer;
    std::vector<fs::path> opened;  // .mtl files, glTF buffers: the result depends on them too
    const aiScene* ai = loom::formats::import_scene(importer, path, aiProcess_GenSmoothNormals, &opened);
    Textures textures(ai, path.parent_path());
    std::vector<loom::Material> materials;
    for (unsigned i = 0; i < ai->mNumMaterials; ++i)
      materials.push_back(material_of(ai->mMaterials[i], textures, in.get<double>("bump_scale"), ctx));
    for (const fs::path& f : opened) ctx.depends_on_file(f);
    for (const fs::path& f : textures.files()) ctx.depends_on_file(f);
    loom::Scene scene;
    const auto transforms = place_objects(*ai, triangle_meshes(*ai), materials, scene);
    if (scene.objects.empty()) throw loom::Error(path.string() + " has no triangle meshes");
    auto placed = [&](const aiString& node_name) {
      auto it = transforms.find(node_name.C_Str());
      return it == transforms.end() ? Eigen::Matrix4d(Eigen::Matrix4d::Identity()) : it->second;
    };
    for (unsigned i = 0; i < ai->mNumLights; ++i)
      if (auto light = light_of(*ai->mLights[i], placed(ai->mLights[i]->mName), ctx)) scene.lights.push_back(*light);
    if (ai->mNumCameras > 0) scene.camera = camera_of(*ai->mCameras[0], placed(ai->mCameras[0]->mName));
    loom::require_valid(scene, "scene");
    out.set("scene", std::move(scene));
  }
};
LOOM_NODE(LoadScene);

}  // namespace
