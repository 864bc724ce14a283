// SaveJSON: writes any value that has a JSON form (numbers, lists, the JSON
// of an NBody's table or events) as a .json file, atomically.
#include <algorithm>
#include <cctype>
#include <filesystem>

#include "loom/atomic_file.hpp"
#include "loom/plugin.hpp"

namespace {

struct SaveJSON {
  static constexpr const char* name = "SaveJSON";
  static void declare(loom::NodeSpec& s) {
    s.describe("Writes a value as JSON: numbers in full (shortest round-trip form, 17 significant digits "
               "at most), lists, objects (e.g. NBody's table and events). Values without a JSON form "
               "(images, meshes) are refused. Nothing on disk changes unless the whole write succeeds.")
        .set_sink()
        .input<loom::Any>("value", "what to write")
        .input<std::string>("path", "the .json file to write, relative to the output folder; {frame:04} in it "
                                    "becomes the frame number (one file per frame)")
        .output_file()
        .input<int>("indent", -1, "spaces per level (-1: one line)").range(-1, 8);
  }
  static void run(loom::Inputs& in, loom::Outputs&, loom::Context& ctx) {
    const std::filesystem::path path = in.get<std::string>("path");
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext != ".json") throw loom::Error("cannot save " + path.string() + ": SaveJSON writes .json files");
    const loom::Value& value = in.value("value");
    if (!value.type() || !value.type()->to_json)
      throw loom::Error("value (" + value.summary() + ") has no JSON form: only numbers, text, lists and JSON can be written");
    ctx.check_cancelled();
    loom::write_file_atomic(path, value.to_json().dump(in.get<int>("indent")) + "\n");
    ctx.log("wrote " + path.string());
  }
};
LOOM_NODE(SaveJSON);

}  // namespace
