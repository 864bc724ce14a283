// Cleaning of control point pairs: NaN dropped, duplicates merged, absurd
// coordinates refused.
#include <cmath>

#include <gtest/gtest.h>

#include "control_points.hpp"
#include "loom/error.hpp"

namespace loom::warp {
namespace {

TEST(ControlPoints, DropsNonFiniteAndMergesNearDuplicates) {
  Eigen::MatrixX2d P(5, 2), Q(5, 2);
  P << 10, 10, NAN, 3, 10.0004, 10, 50, 50, 10, 10;
  Q << 0, 0, 1, 1, 6, 0, 60, 60, 3, 3;
  std::vector<std::string> notes;
  const ControlPoints cp = clean_control_points(P, Q, 1e-3, &notes);
  ASSERT_EQ(cp.p.rows(), 2);
  EXPECT_EQ(cp.p.row(0), Eigen::RowVector2d(10, 10));
  EXPECT_NEAR(cp.q(0, 0), 3.0, 1e-12);  // mean of 0, 6, 3
  EXPECT_NEAR(cp.q(0, 1), 1.0, 1e-12);  // mean of 0, 0, 3
  EXPECT_EQ(cp.p.row(1), Eigen::RowVector2d(50, 50));
  ASSERT_EQ(notes.size(), 3u);
  EXPECT_NE(notes[0].find("pair 1"), std::string::npos);
  EXPECT_NE(notes[1].find("pair 2"), std::string::npos);
}

TEST(ControlPoints, RefusesHugeCoordinates) {
  Eigen::MatrixX2d P(1, 2), Q(1, 2);
  P << 1e300, 0;
  Q << 0, 0;
  EXPECT_THROW(clean_control_points(P, Q, 1e-3, nullptr), Error);
}

}  // namespace
}  // namespace loom::warp
