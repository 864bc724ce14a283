// Built-in value types: literal parsing, error messages, round trips.
#include <gtest/gtest.h>

#include "loom/builtin_types.hpp"
#include "loom/point_pairs.hpp"

namespace loom {
namespace {

TEST(Values, ScalarsRoundTrip) {
  EXPECT_EQ(TypeTraits<int>::from_json(json(3)), 3);
  EXPECT_EQ(TypeTraits<int>::from_json(json(3.0)), 3);
  EXPECT_DOUBLE_EQ(TypeTraits<double>::from_json(json(0.25)), 0.25);
  EXPECT_TRUE(TypeTraits<bool>::from_json(json(true)));
  EXPECT_EQ(TypeTraits<Vec2i>::from_json(json::parse("[3, 4]")), Vec2i(3, 4));
}

TEST(Values, ErrorsSayWhatWasExpected) {
  try {
    TypeTraits<int>::from_json(json(2.5));
    FAIL() << "2.5 accepted as an integer";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "expected an integer, got 2.5 (a number)");
  }
  EXPECT_THROW(TypeTraits<Vec2>::from_json(json::parse("[1]")), Error);
  EXPECT_THROW(TypeTraits<Color>::from_json(json("#12345")), Error);
}

TEST(Values, ColorFromHex) {
  Color c = TypeTraits<Color>::from_json(json("#ff000080"));
  EXPECT_DOUBLE_EQ(c.rgba[0], 1.0);
  EXPECT_DOUBLE_EQ(c.rgba[1], 0.0);
  EXPECT_NEAR(c.rgba[3], 128 / 255.0, 1e-12);
}

TEST(Values, ColorComponentsStayWhereFloatPixelsCanHoldThem) {
  // 1e300 would become an infinite float pixel; HDR emission stays far below 1e6.
  EXPECT_THROW(TypeTraits<Color>::from_json(json::parse("[1e300, 0, 0]")), Error);
  EXPECT_THROW(TypeTraits<Color>::from_json(json::parse("[0, -2e6, 0]")), Error);
  EXPECT_EQ(TypeTraits<Color>::from_json(json::parse("[1e6, 50, 0.5]")).rgba[0], 1e6);
}

TEST(Values, PointPairsBothForms) {
  PointPairs a = TypeTraits<PointPairs>::from_json(json::parse("[[1, 2, 3, 4]]"));
  PointPairs b = TypeTraits<PointPairs>::from_json(json::parse(R"([{"p": [1, 2], "q": [3, 4]}])"));
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a.p[0], b.p[0]);
  EXPECT_EQ(a.q[0], Vec2(3, 4));
  EXPECT_THROW(TypeTraits<PointPairs>::from_json(json::parse("[[1, 2, 3]]")), Error);
}

TEST(Values, TypesAreRegisteredOnceByName) {
  const TypeInfo& a = type_of<double>();
  EXPECT_EQ(find_type("Float"), &a);
  EXPECT_EQ(enum_type().storage, "String");
  Value v = Value::make<std::string>("x");
  EXPECT_TRUE(v.is<std::string>());
  EXPECT_THROW(v.as<double>(), Error);
}

}  // namespace
}  // namespace loom
