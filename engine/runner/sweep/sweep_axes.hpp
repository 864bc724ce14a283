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
// Throws Error when --zip is given lists of different lengths.
std::vector<SweepPoint> sweep_points(const std::vector<SweepAxis>& axes, bool zip);

}  // namespace loom::runner
