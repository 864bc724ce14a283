// LoadMesh: a mesh file as a loom::Mesh, its vertex list kept as the file has it.
#include "loom/input_file.hpp"
#include "loom/mesh.hpp"
#include "loom/plugin.hpp"
#include "mesh_codec.hpp"

namespace {

struct LoadMesh {
  static constexpr const char* name = "LoadMesh";
  static void declare(loom::NodeSpec& s) {
    s.describe("Reads OBJ, PLY, OFF, glTF/GLB, STL and the other formats assimp knows. OBJ, PLY "
               "and OFF keep the file's vertices, their order and the faces' indices exactly (a "
               "mesh cut along a seam stays cut); a vertex whose face corners carry different "
               "UVs or normals is split, the copies appended. Polygons are fan-triangulated. "
               "UVs/normals/colors are kept when every corner has them.")
        .set_version(2)
        .input<std::string>("path", "the mesh file, relative to the graph file").input_file()
        .input<bool>("weld", false,
                     "join vertices closer than `weld_tolerance` (off: the file's vertices as they are)")
        .input<double>("weld_tolerance", 0.0, "distance below which `weld` joins vertices (0: identical positions)")
        .range(0, 1e300)
        .output<loom::Mesh>("mesh", "the triangles");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx) {
    loom::require_input_file(in.get<std::string>("path"), "mesh", ctx.graph_dir());
    loom::io::MeshNotes notes;
    loom::Mesh mesh = loom::io::read_mesh(in.get<std::string>("path"), &notes);
    if (notes.dropped_primitives > 0)
      ctx.warn("dropped " + std::to_string(notes.dropped_primitives) + " line and point primitives");
    for (const auto& m : notes.messages) ctx.warn(m);
    if (notes.split_vertices > 0)
      ctx.log("split " + std::to_string(notes.split_vertices) +
              " vertices whose corners carry different UVs or normals");
    if (in.get<bool>("weld")) {
      const int merged = loom::io::weld_vertices(mesh, in.get<double>("weld_tolerance"));
      ctx.log("weld: merged " + std::to_string(merged) + " vertices");
      if (mesh.faces() == 0) throw loom::Error("weld collapsed every face: weld_tolerance is too large");
    }
    ctx.log(loom::TypeTraits<loom::Mesh>::summary(mesh));
    out.set("mesh", std::move(mesh));
  }
};
LOOM_NODE(LoadMesh);

}  // namespace
