// SaveMesh: writes a mesh file atomically.
#include "loom/mesh.hpp"
#include "loom/plugin.hpp"
#include "mesh_codec.hpp"

namespace {

struct SaveMesh {
  static constexpr const char* name = "SaveMesh";
  static void declare(loom::NodeSpec& s) {
    s.describe("Writes OBJ (with a .mtl material) or PLY with the mesh's vertex list as it is, or "
               "glTF, GLB or STL through assimp (whose glTF export joins identical vertices), keeping "
               "UVs, normals and colors the format can hold. Nothing on disk changes unless the whole "
               "write succeeds.")
        .set_version(2)
        .set_sink()
        .input<loom::Mesh>("mesh", "the mesh to write")
        .input<std::string>("path", "the file to write, relative to the output folder; {frame:04} in it becomes the frame number (one file per frame)").output_file()
        .input<std::string>("texture", std::string(),
                            "an image file name for the material's diffuse map (OBJ, glTF)");
  }
  static void run(loom::Inputs& in, loom::Outputs&, loom::Context& ctx) {
    const std::string& path = in.get<std::string>("path");
    loom::io::write_mesh(in.get<loom::Mesh>("mesh"), path, in.get<std::string>("texture"),
                         [&ctx] { ctx.check_cancelled(); });
    ctx.log("wrote " + path);
  }
};
LOOM_NODE(SaveMesh);

}  // namespace
