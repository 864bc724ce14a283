// Cleaning control point pairs before a fit, so that no fit sees NaN or two
// sources at one place (which would make its system singular).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace loom::warp {

struct ControlPoints {
  Eigen::MatrixX2d p;  // #n by 2 sources, pairwise farther apart than the merge distance
  Eigen::MatrixX2d q;  // #n by 2 targets
};

// Coordinates farther than this from the origin are refused (they are typos,
// and their squares would lose all precision of in-image distances).
constexpr double kMaxCoordinate = 1e7;

// Drops pairs with a NaN or infinite coordinate, and merges pairs whose sources
// lie within merge_distance of an earlier kept source (their targets are
// averaged). Throws loom::Error for a coordinate beyond ±kMaxCoordinate.
//   P, Q   #pairs by 2 sources and targets, pixels
//   notes  one line per dropped or merged pair, naming its index
ControlPoints clean_control_points(const Eigen::MatrixX2d& P, const Eigen::MatrixX2d& Q,
                                   double merge_distance, std::vector<std::string>* notes);

}  // namespace loom::warp
