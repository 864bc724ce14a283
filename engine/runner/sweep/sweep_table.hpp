// A sweep's tables: OUT/sweep.csv (one row per point: the swept values, the
// status, the seconds of the whole point and of each node, every --record
// value flattened to its numeric leaves, a list by its last value) and
// OUT/sweep.json (the same with lists kept whole), and --plot X:Y as
// OUT/sweep_X_Y.png drawn by gnuplot, as the benchmarks draw theirs.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "sweep/sweep_axes.hpp"

namespace loom::runner {

// `points` are the points' point.json documents. False (and an error printed)
// when a file could not be written or a plot names an unknown column.
bool write_sweep_tables(const std::filesystem::path& out, const std::vector<SweepAxis>& axes,
                        const std::vector<json>& points, const std::vector<std::string>& plots, bool quiet);

}  // namespace loom::runner
