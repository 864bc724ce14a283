// Figure validation: errors name the figure index, its type and the key.
#include <gtest/gtest.h>

#include "figures.hpp"
#include "loom/error.hpp"

namespace loom::draw {
namespace {

std::string error_of(const json& figures) {
  try {
    parse_figures(figures);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Figures, ParsesEveryType) {
  const json figures = json::parse(R"([
    {"type": "line", "from": [0, 0], "to": [10, 10]},
    {"type": "arrow", "from": [0, 0], "to": [10, 10], "head": 5, "width": 2, "stroke": "#ff0000"},
    {"type": "rectangle", "min": [1, 2], "max": [3, 4], "fill": [0, 1, 0]},
    {"type": "rounded_rectangle", "min": [1, 2], "max": [30, 40], "radius": 5},
    {"type": "ellipse", "center": [5, 5], "axes": [3, 2], "angle": 30},
    {"type": "polygon", "points": [[0, 0], [5, 0], [0, 5]], "fill_rule": "evenodd"},
    {"type": "freehand", "points": [[0, 0], [1, 1], [2, 1]]}])");
  const std::vector<Figure> f = parse_figures(figures);
  ASSERT_EQ(f.size(), 7u);
  EXPECT_EQ(f[1].stroke.rgba, Eigen::Vector4d(1, 0, 0, 1));
  EXPECT_TRUE(f[2].fill.has_value());
  EXPECT_EQ(f[5].fill_rule, FillRule::evenodd);
  EXPECT_EQ(figure_outline(f[2]).size(), 4u);
  EXPECT_GT(figure_outline(f[4]).size(), 16u);
}

TEST(Figures, ErrorsNameIndexTypeAndKey) {
  EXPECT_EQ(error_of(json::parse(R"([{"type": "line", "from": [0, 0], "to": [1, 1]},
                                     {"type": "ellipse", "center": [5, 5]}])")),
            "figure 1 (ellipse): key \"axes\" is missing");
  EXPECT_NE(error_of(json::parse(R"([{"type": "line", "from": [0, 0], "to": "x"}])")).find("figure 0 (line): key \"to\""),
            std::string::npos);
  EXPECT_NE(error_of(json::parse(R"([{"type": "line", "from": [0, 0], "to": [1, 1], "fill": "#ffffff"}])"))
                .find("only closed figures are filled"),
            std::string::npos);
  EXPECT_NE(error_of(json::parse(R"([{"type": "circle"}])")).find("expected one of"), std::string::npos);
  EXPECT_NE(error_of(json::parse(R"([{"type": "polygon", "points": [[0, 0], [1, 1]]}])")).find("at least 3 points"),
            std::string::npos);
  EXPECT_NE(error_of(json::parse(R"([{"type": "rectangle", "min": [0, 0], "max": [1, 1], "widht": 2}])"))
                .find("key \"widht\" is not a key of a rectangle"),
            std::string::npos);
  EXPECT_NE(error_of(json::parse(R"([{"type": "rectangle", "min": [5, 5], "max": [1, 1]}])")).find("\"max\""),
            std::string::npos);
  EXPECT_NE(error_of(json::parse(R"({"type": "line"})")).find("expected a list"), std::string::npos);
}

}  // namespace
}  // namespace loom::draw
