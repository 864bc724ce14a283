// One node's body run outside any graph (loom/call_node.hpp), as the runner's
// --preview runs SaveImage and the editor's viewer runs DisplayView: given
// values and literals, the other inputs at their defaults, literals checked
// as a graph file's are, and the values a node reads by reference alive for
// the whole call.
#include <gtest/gtest.h>

#include "loom/call_node.hpp"
#include "loom/error.hpp"
#include "loom/testing.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

struct CallNode : ::testing::Test {
  testing::Engine engine;
  void SetUp() override { engine.load_plugins({"Math", "WriteText"}); }
  const NodeType& type(const std::string& name) { return *engine.registry().find(name); }
};

TEST_F(CallNode, ValuesLiteralsAndDefaults) {
  NodeCall call;
  call.values.emplace("a", Value::make<double>(2.0));
  call.literals = {{"op", "power"}, {"b", 10}};
  const std::vector<Value> out = call_node(type("Math"), call);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].as<double>(), 1024.0);
  EXPECT_EQ(call_node(type("Math"), NodeCall{}).at(0).as<double>(), 0.0);  // 0 add 0, every input at its default
}

TEST_F(CallNode, AStringReadByReferenceLastsTheCall) {
  const auto file = test::temp_dir() / "value.txt";
  NodeCall call;
  call.values.emplace("value", Value::make<double>(1.5));
  call.literals["path"] = file.string();
  call_node(type("WriteText"), call);
  EXPECT_EQ(test::read_text(file), "1.500000\n");
}

TEST_F(CallNode, RefusesWhatAGraphFileWouldBeRefused) {
  const auto refused = [&](const std::string& node, NodeCall call, const std::string& says) {
    try {
      call_node(type(node), call);
      ADD_FAILURE() << node << ": no error, expected one saying " << says;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  NodeCall bad_choice;
  bad_choice.literals["op"] = "modulo";
  refused("Math", bad_choice, "Math's input \"op\"");
  NodeCall unknown;
  unknown.literals["c"] = 1;
  refused("Math", unknown, "Math has no input \"c\"");
  NodeCall missing;
  missing.literals["path"] = (test::temp_dir() / "x.txt").string();
  refused("WriteText", missing, "WriteText's input \"value\" is required");
}

}  // namespace
}  // namespace loom
