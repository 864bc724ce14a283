#include "figures.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "loom/error.hpp"

namespace loom::draw {

namespace {

const std::map<std::string, FigureType>& type_names() {
  static const std::map<std::string, FigureType> names = {
      {"line", FigureType::line},           {"arrow", FigureType::arrow},
      {"rectangle", FigureType::rectangle}, {"rounded_rectangle", FigureType::rounded_rectangle},
      {"ellipse", FigureType::ellipse},     {"polygon", FigureType::polygon},
      {"freehand", FigureType::freehand}};
  return names;
}

// The keys each type accepts besides type, stroke and width (and fill when closed).
std::set<std::string> own_keys(FigureType t) {
  switch (t) {
    case FigureType::line: return {"from", "to"};
    case FigureType::arrow: return {"from", "to", "head"};
    case FigureType::rectangle: return {"min", "max"};
    case FigureType::rounded_rectangle: return {"min", "max", "radius"};
    case FigureType::ellipse: return {"center", "axes", "angle"};
    case FigureType::polygon: return {"points", "fill_rule"};
    case FigureType::freehand: return {"points"};
  }
  return {};
}

// Reads key k of figure object o with `read`, naming the key on error.
template <class Read>
auto key(const json& o, const std::string& k, Read read) {
  if (!o.contains(k)) throw Error("key \"" + k + "\" is missing");
  try {
    return read(o.at(k));
  } catch (const Error& e) {
    throw Error("key \"" + k + "\": " + e.what());
  }
}

Vec2 point(const json& j) {
  const Vec2 v = TypeTraits<Vec2>::from_json(j);
  if (!v.allFinite() || v.cwiseAbs().maxCoeff() > 1e7) throw Error("expected a point within ±1e7 pixels");
  return v;
}

double number(const json& j, double lo, double hi) {
  if (!j.is_number()) throw Error("expected a number, got " + describe_json(j));
  const double v = j.get<double>();
  if (!(v >= lo && v <= hi))
    throw Error("expected a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + describe_json(j));
  return v;
}

std::vector<Eigen::Vector2d> points(const json& j, std::size_t at_least) {
  if (!j.is_array()) throw Error("expected a list of [x, y] points, got " + describe_json(j));
  std::vector<Eigen::Vector2d> p;
  for (std::size_t i = 0; i < j.size(); ++i) {
    try {
      p.push_back(point(j[i]));
    } catch (const Error& e) {
      throw Error("point " + std::to_string(i) + ": " + e.what());
    }
  }
  if (p.size() < at_least)
    throw Error("expected at least " + std::to_string(at_least) + " points, got " + std::to_string(p.size()));
  return p;
}

Figure parse_figure(const json& o) {
  if (!o.is_object()) throw Error("expected an object {\"type\": ..., ...}, got " + describe_json(o));
  const std::string type = key(o, "type", [](const json& j) {
    if (!j.is_string() || !type_names().count(j.get<std::string>())) {
      std::string all;
      for (const auto& [name, t] : type_names()) all += (all.empty() ? "" : ", ") + name;
      throw Error("expected one of " + all + ", got " + describe_json(j));
    }
    return j.get<std::string>();
  });
  Figure f;
  f.type = type_names().at(type);
  std::set<std::string> allowed = own_keys(f.type);
  allowed.insert({"type", "stroke", "width"});
  if (is_closed(f.type)) allowed.insert("fill");
  for (const auto& item : o.items())
    if (!allowed.count(item.key()))
      throw Error("key \"" + item.key() + "\" is not a key of a " + type +
                  (item.key() == "fill" ? " (only closed figures are filled)" : ""));

  if (o.contains("stroke")) f.stroke = key(o, "stroke", TypeTraits<Color>::from_json);
  if (o.contains("width")) f.width = key(o, "width", [](const json& j) { return number(j, 0, 1000); });
  if (o.contains("fill")) f.fill = key(o, "fill", TypeTraits<Color>::from_json);
  switch (f.type) {
    case FigureType::line:
    case FigureType::arrow:
      f.points = {key(o, "from", point), key(o, "to", point)};
      if (o.contains("head")) f.head = key(o, "head", [](const json& j) { return number(j, 0, 1e4); });
      break;
    case FigureType::rectangle:
    case FigureType::rounded_rectangle:
      f.min = key(o, "min", point);
      f.max = key(o, "max", point);
      if (f.max.x() < f.min.x() || f.max.y() < f.min.y())
        throw Error("key \"max\": must not be left of or above \"min\"");
      if (o.contains("radius")) f.radius = key(o, "radius", [](const json& j) { return number(j, 0, 1e7); });
      break;
    case FigureType::ellipse:
      f.center = key(o, "center", point);
      f.axes = key(o, "axes", point);
      if (f.axes.minCoeff() < 0) throw Error("key \"axes\": radii must not be negative");
      if (o.contains("angle")) f.angle = key(o, "angle", [](const json& j) { return number(j, -1e6, 1e6); });
      break;
    case FigureType::polygon:
      f.points = key(o, "points", [](const json& j) { return points(j, 3); });
      if (o.contains("fill_rule"))
        f.fill_rule = key(o, "fill_rule", [](const json& j) {
          if (j == "nonzero") return FillRule::nonzero;
          if (j == "evenodd") return FillRule::evenodd;
          throw Error("expected \"nonzero\" or \"evenodd\", got " + describe_json(j));
        });
      break;
    case FigureType::freehand:
      f.points = key(o, "points", [](const json& j) { return points(j, 2); });
      break;
  }
  return f;
}

// Points of an elliptic arc, enough that chords stay within 0.05 px of it,
// on radii scaled by sqrt(θ / sin θ) (θ the angle per chord) so that each
// chord triangle has the area of its sector: the filled area is exact.
void append_arc(std::vector<Eigen::Vector2d>& out, const Eigen::Vector2d& c, double rx, double ry, double angle,
                double from, double to) {
  const double r = std::max({rx, ry, 1e-9});
  const double step = 2 * std::acos(std::max(-1.0, 1 - 0.05 / r));  // chord sagitta 0.05 px
  const int n = std::clamp(static_cast<int>(std::ceil(std::abs(to - from) / step)), 2, 20000);
  const double theta = std::abs(to - from) / n;
  const double grow = std::sqrt(theta / std::sin(theta));
  const double ca = std::cos(angle), sa = std::sin(angle);
  for (int k = 0; k <= n; ++k) {
    const double t = from + (to - from) * k / n;
    const double x = grow * rx * std::cos(t), y = grow * ry * std::sin(t);
    out.emplace_back(c.x() + ca * x - sa * y, c.y() + sa * x + ca * y);
  }
}

}  // namespace

bool is_closed(FigureType t) {
  return t == FigureType::rectangle || t == FigureType::rounded_rectangle || t == FigureType::ellipse ||
         t == FigureType::polygon;
}

std::vector<Figure> parse_figures(const json& figures) {
  if (!figures.is_array()) throw Error("figures: expected a list of figure objects, got " + describe_json(figures));
  std::vector<Figure> out;
  for (std::size_t i = 0; i < figures.size(); ++i) {
    try {
      out.push_back(parse_figure(figures[i]));
    } catch (const Error& e) {
      const json& t = figures[i].is_object() && figures[i].contains("type") ? figures[i]["type"] : json();
      throw Error("figure " + std::to_string(i) + (t.is_string() ? " (" + t.get<std::string>() + ")" : "") + ": " +
                  e.what());
    }
  }
  return out;
}

std::vector<Eigen::Vector2d> figure_outline(const Figure& f) {
  switch (f.type) {
    case FigureType::rectangle:
      return {f.min, {f.max.x(), f.min.y()}, f.max, {f.min.x(), f.max.y()}};
    case FigureType::rounded_rectangle: {
      const double r = std::min({f.radius, (f.max.x() - f.min.x()) / 2, (f.max.y() - f.min.y()) / 2});
      if (r <= 0) return {f.min, {f.max.x(), f.min.y()}, f.max, {f.min.x(), f.max.y()}};
      std::vector<Eigen::Vector2d> out;
      const double h = M_PI / 2;  // corners clockwise on screen from the top-left
      append_arc(out, {f.min.x() + r, f.min.y() + r}, r, r, 0, 2 * h, 3 * h);
      append_arc(out, {f.max.x() - r, f.min.y() + r}, r, r, 0, 3 * h, 4 * h);
      append_arc(out, {f.max.x() - r, f.max.y() - r}, r, r, 0, 0, h);
      append_arc(out, {f.min.x() + r, f.max.y() - r}, r, r, 0, h, 2 * h);
      return out;
    }
    case FigureType::ellipse: {
      std::vector<Eigen::Vector2d> out;
      append_arc(out, f.center, f.axes.x(), f.axes.y(), f.angle * M_PI / 180, 0, 2 * M_PI);
      out.pop_back();  // the closing point repeats the first
      return out;
    }
    default:
      return f.points;
  }
}

}  // namespace loom::draw
