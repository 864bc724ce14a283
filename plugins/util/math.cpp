// Math: one binary operation on real numbers.
#include <algorithm>
#include <cmath>

#include "loom/plugin.hpp"

namespace {

struct Math {
  static constexpr const char* name = "Math";
  static void declare(loom::NodeSpec& s) {
    s.describe("result = a OP b on real numbers.")
        .input<double>("a", 0.0, "left operand")
        .input<double>("b", 0.0, "right operand")
        .enum_input("op", "add", {"add", "subtract", "multiply", "divide", "power", "min", "max"},
                    "the operation")
        .output<double>("result", "a OP b");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    const double a = in.get<double>("a"), b = in.get<double>("b");
    const std::string& op = in.get<std::string>("op");
    double r = 0;
    if (op == "add") r = a + b;
    else if (op == "subtract") r = a - b;
    else if (op == "multiply") r = a * b;
    else if (op == "divide") {
      if (b == 0) throw loom::Error("division by zero: b is 0");
      r = a / b;
    } else if (op == "power") r = std::pow(a, b);
    else if (op == "min") r = std::min(a, b);
    else r = std::max(a, b);
    if (!std::isfinite(r))
      throw loom::Error(op + " of " + std::to_string(a) + " and " + std::to_string(b) +
                        " is not a finite number");
    out.set("result", r);
  }
};
LOOM_NODE(Math);

}  // namespace
