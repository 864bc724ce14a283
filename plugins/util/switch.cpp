// Switch: passes one of its inputs through. Its inputs are lazy, so the
// branches it does not select are never computed.
#include "loom/plugin.hpp"

namespace {

struct Switch {
  static constexpr const char* name = "Switch";
  static void declare(loom::NodeSpec& s) {
    s.describe("Passes input number `index` through; the other inputs are never computed.")
        .input<int>("index", 0, "which input to pass through").range(0, 3)
        .input<loom::Any>("in0", "choice 0").optional().lazy()
        .input<loom::Any>("in1", "choice 1").optional().lazy()
        .input<loom::Any>("in2", "choice 2").optional().lazy()
        .input<loom::Any>("in3", "choice 3").optional().lazy()
        .output<loom::Any>("value", "the selected input");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    const std::string chosen = "in" + std::to_string(in.get<int>("index"));
    if (!in.has(chosen)) throw loom::Error("index selects " + chosen + ", which is not linked");
    out.set_value("value", in.value(chosen));
  }
};
LOOM_NODE(Switch);

}  // namespace
