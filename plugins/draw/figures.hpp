// Figures as plain JSON (so the editor can draw them interactively), parsed
// and validated into geometry. One figure is an object:
//
//   {"type": "line",              "from": [x, y], "to": [x, y]}
//   {"type": "arrow",             "from": [x, y], "to": [x, y], "head": 12}
//   {"type": "rectangle",         "min": [x, y], "max": [x, y]}
//   {"type": "rounded_rectangle", "min": [x, y], "max": [x, y], "radius": 8}
//   {"type": "ellipse",           "center": [x, y], "axes": [rx, ry], "angle": 0}
//   {"type": "polygon",           "points": [[x, y], ...], "fill_rule": "nonzero"}
//   {"type": "freehand",          "points": [[x, y], ...]}
//
// plus, for every type, "stroke" (a Color, default black), "width" (pixels,
// default 1, 0 = no outline) and, for closed types, "fill" (a Color; no fill
// when absent). Coordinates are pixels, origin top-left, pixel centers at +0.5.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "loom/builtin_types.hpp"
#include "polygon_fill.hpp"

namespace loom::draw {

enum class FigureType { line, arrow, rectangle, rounded_rectangle, ellipse, polygon, freehand };

struct Figure {
  FigureType type = FigureType::line;
  std::vector<Eigen::Vector2d> points;  // line/arrow: from, to; polygon/freehand: the points
  Eigen::Vector2d min{0, 0}, max{0, 0};  // rectangles
  Eigen::Vector2d center{0, 0}, axes{0, 0};  // ellipse
  double angle = 0;    // ellipse, degrees, clockwise on screen (y down)
  double radius = 0;   // rounded_rectangle corner radius
  double head = 12;    // arrow head length in pixels
  FillRule fill_rule = FillRule::nonzero;
  Color stroke;
  double width = 1;
  std::optional<Color> fill;
};

// Parses a JSON array of figures. Throws loom::Error naming the figure index
// and the key: "figure 2 (ellipse): key \"axes\": expected ...".
std::vector<Figure> parse_figures(const json& figures);

// The closed outline of a closed figure as a polygon (ellipse and rounded
// corners flattened to within 0.05 px, enclosing their exact area), or the
// points of an open one.
std::vector<Eigen::Vector2d> figure_outline(const Figure& f);

bool is_closed(FigureType t);

}  // namespace loom::draw
