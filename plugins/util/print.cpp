// Print: a sink that logs a one-line summary of any value.
#include "loom/plugin.hpp"

namespace {

struct Print {
  static constexpr const char* name = "Print";
  static void declare(loom::NodeSpec& s) {
    s.describe("Logs a one-line summary of a value (a sink: it always runs).")
        .set_sink()
        .input<loom::Any>("value", "what to print")
        .input<std::string>("label", std::string(), "printed before the value");
  }
  static void run(loom::Inputs& in, loom::Outputs&, loom::Context& ctx) {
    const std::string& label = in.get<std::string>("label");
    ctx.log((label.empty() ? "" : label + ": ") + in.value("value").summary());
  }
};
LOOM_NODE(Print);

}  // namespace
