// `loom run --sweep`: one graph run at every point of a parameter sweep (a
// wedge), in one process and one Session, so every result upstream of the
// swept inputs is computed once and shared by the points. Writes
// OUT/points/NNNN/ (each point's output files and point.json), OUT/sweep.csv
// (a row per point: values, status, seconds per node, --record values
// flattened to numeric leaves), OUT/sweep.json (the same, lists kept whole),
// and with --plot X:Y a PNG drawn by gnuplot. See docs/farm.md.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/run_settings.hpp"
#include "loom/evaluator.hpp"

namespace loom::runner {

// Points handed out one at a time as the process asks for them (MPI ranks
// with --mpi-deal dynamic, mpi_run.cpp) instead of --sweep-points.
struct PointDealing {
  std::function<long()> next;  // the next point to run, -1 when none is left
  // Runs one point's evaluation (rank 0 lets MPI answer the other ranks meanwhile).
  std::function<EvalResult(const std::function<EvalResult()>&)> evaluate;
};

struct SweepRequest {
  std::vector<std::string> axes;     // --sweep ID.INPUT=...
  bool zip = false;                  // --zip
  std::vector<std::string> records;  // --record ID.OUTPUT or ID
  std::vector<std::string> plots;    // --plot X:Y (column names of sweep.csv)
  std::string only;                  // --sweep-points I,J,...: run only these (a submitted task)
  bool collect = false;              // --sweep-collect: gather the points' files, run nothing
  const PointDealing* dealt = nullptr;  // run the points it hands out (no tables), not `only`
  bool active() const { return !axes.empty(); }
};

void add_sweep_options(CLI::App* run, SweepRequest& request);
int run_sweep(const SweepRequest& request, const RunSettings& settings);
// Checks the sweep as run_sweep does before running anything (every point's
// graph validated, the --record outputs exist): the number of points, or
// nullopt with the error printed.
std::optional<std::size_t> check_sweep(const SweepRequest& request, const RunSettings& settings,
                                       const LoadedGraph& graph);

}  // namespace loom::runner
