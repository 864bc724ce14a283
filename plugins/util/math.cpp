// Math: one binary operation on real numbers.
#include <algorithm>
#include <cmath>

#include "loom/plugin.hpp"

namespace {

enum class Op { add, subtract, multiply, divide, power, min, max };

struct Math {
  static constexpr const char* name = "Math";
  static void declare(loom::NodeSpec& s) {
    s.describe("result = a OP b on real numbers.")
        .input<double>("a", 0.0, "left operand")
        .input<double>("b", 0.0, "right operand")
        .enum_input("op", Op::add,
                    {{Op::add, "add"},
                     {Op::subtract, "subtract"},
                     {Op::multiply, "multiply"},
                     {Op::divide, "divide"},
                     {Op::power, "power"},
                     {Op::min, "min"},
                     {Op::max, "max"}},
                    "the operation")
        .output<double>("result", "a OP b");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    const double a = in.get<double>("a"), b = in.get<double>("b");
    double r = 0;
    switch (in.get<Op>("op")) {
      case Op::add: r = a + b; break;
      case Op::subtract: r = a - b; break;
      case Op::multiply: r = a * b; break;
      case Op::divide:
        if (b == 0) throw loom::Error("division by zero: b is 0");
        r = a / b;
        break;
      case Op::power: r = std::pow(a, b); break;
      case Op::min: r = std::min(a, b); break;
      case Op::max: r = std::max(a, b); break;
    }
    if (!std::isfinite(r))
      throw loom::Error(in.get<std::string>("op") + " of " + loom::TypeTraits<double>::summary(a) + " and " +
                        loom::TypeTraits<double>::summary(b) + " is not a finite number");
    out.set("result", r);
  }
};
LOOM_NODE(Math);

}  // namespace
