// Constant nodes: one value, set in the graph file or by `--set`, fanned out
// to many inputs.
#include "loom/plugin.hpp"

namespace {

template <class T, const char* Name, const char* Description>
struct Constant {
  static constexpr const char* name = Name;
  static void declare(loom::NodeSpec& s) {
    s.describe(Description).template input<T>("value", T{}, "the value").template output<T>("value", "the same value");
  }
  static void run(loom::Inputs& in, loom::Outputs& out, loom::Context&) {
    out.share<T>("value", in.share<T>("value"));
  }
};

constexpr char kFloat[] = "FloatConstant", kFloatText[] = "A number.";
constexpr char kInt[] = "IntConstant", kIntText[] = "An integer.";
constexpr char kBool[] = "BoolConstant", kBoolText[] = "true or false.";
constexpr char kString[] = "StringConstant", kStringText[] = "A piece of text.";

using FloatConstant = Constant<double, kFloat, kFloatText>;
using IntConstant = Constant<int, kInt, kIntText>;
using BoolConstant = Constant<bool, kBool, kBoolText>;
using StringConstant = Constant<std::string, kString, kStringText>;

LOOM_NODE(FloatConstant);
LOOM_NODE(IntConstant);
LOOM_NODE(BoolConstant);
LOOM_NODE(StringConstant);

}  // namespace
