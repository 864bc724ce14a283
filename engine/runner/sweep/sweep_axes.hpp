// The values a sweep walks: `--sweep ID.INPUT=V1,V2,...` (JSON values, as
// --set takes them), or a range `A:B:N` (N values from A to B, evenly spaced)
// or `A:B:N:log` (evenly spaced in log A .. log B); an Int input's values are
// rounded. Several axes form the Cartesian product (the first axis varies
// slowest), or with --zip the i-th values of every axis together.
#pragma once

#include <string>
#include <vector>

#include "loom/graph_view.hpp"

namespace loom::runner {

struct SweepAxis {
  std::string input;                // "ID.INPUT"
  std::vector<json> values;
};

struct SweepPoint {
  std::vector<std::string> assignments;  // "ID.INPUT=JSON", as --set takes them
  json values;                           // {"ID.INPUT": value, ...}
};

// Throws Error naming the --sweep argument and what is wrong with it.
// The input is any address --set takes (the engine's view resolves it).
SweepAxis parse_sweep_axis(const std::string& spec, const GraphView& view);
// Points one sweep may have (LOOM_MAX_SWEEP_POINTS raises it): every
// point's graph is built and validated before any runs, a few kilobytes
// each, so a grid of 1000 × 1000 values took gigabytes before its first point.
constexpr std::size_t kMaxSweepPoints = 100000;
// kMaxSweepPoints, or LOOM_MAX_SWEEP_POINTS when set (throws Error when it is
// not a number above 0).
std::size_t max_sweep_points();
// The number of points, counted without overflow; throws Error naming the
// limit when there are more than max_sweep_points(), and when --zip is given
// lists of different lengths.
std::size_t count_sweep_points(const std::vector<SweepAxis>& axes, bool zip);
// Every point, after count_sweep_points.
std::vector<SweepPoint> sweep_points(const std::vector<SweepAxis>& axes, bool zip);

}  // namespace loom::runner
