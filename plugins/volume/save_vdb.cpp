// SaveVDB: a Volume as an OpenVDB file, one per frame, for Blender, Houdini
// and any tool that reads OpenVDB.
#include "loom/plugin.hpp"
#include "vdb_file.hpp"

namespace {

struct SaveVDB {
  static constexpr const char* name = "SaveVDB";
  static void declare(loom::NodeSpec& s) {
    s.describe("Writes a volume's grids (density, velocity) as an OpenVDB file, which Blender imports as a "
               "Volume object and Houdini as VDB primitives. The file's metadata names the node, its seed and "
               "the frame. Nothing on disk changes unless the whole write succeeds; equal grids give equal "
               "bytes.")
        .set_sink()
        .input<loom::volume::Volume>("volume", "the grids, e.g. PointsToVolume's volume")
        .input<std::string>("path", "the .vdb file to write, relative to the output folder; {frame:04} in it "
                                    "becomes the frame number (one file per frame)")
        .output_file();
  }
  static void run(loom::Inputs& in, loom::Outputs&, loom::Context& ctx) {
    const std::string& path = in.get<std::string>("path");
    const std::string node = ctx.node_id(), seed = std::to_string(ctx.seed()), frame = std::to_string(ctx.time().frame);
    ctx.check_cancelled();
    loom::volume::write_vdb(in.get<loom::volume::Volume>("volume"), path,
                            {{"loom:node", node}, {"loom:seed", seed}, {"loom:frame", frame}});
    ctx.log("wrote " + path);
  }
};
LOOM_NODE(SaveVDB);

}  // namespace
