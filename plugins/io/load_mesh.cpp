// LoadMesh: a mesh file as a loom::Mesh.
#include "loom/mesh.hpp"
#include "loom/plugin.hpp"
#include "mesh_codec.hpp"

namespace {

struct LoadMesh {
  static constexpr const char* name = "LoadMesh";
  static void declare(loom::NodeSpec& s) {
    s.describe("Reads OBJ, PLY, glTF/GLB, STL, OFF and the other formats assimp knows: every "
               "triangle of the file, identical vertices joined, UVs/normals/colors kept.")
        .input<std::string>("path", "the mesh file, relative to the graph file").input_file()
        .output<loom::Mesh>("mesh", "the triangles");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    int dropped = 0;
    loom::Mesh mesh = loom::io::read_mesh(in.get<std::string>("path"), &dropped);
    if (dropped > 0) ctx.warn("dropped " + std::to_string(dropped) + " line and point primitives");
    ctx.log(loom::TypeTraits<loom::Mesh>::summary(mesh));
    out.set("mesh", std::move(mesh));
  }
};
LOOM_NODE(LoadMesh);

}  // namespace
