// The reachability search's moves: straight along the robot's heading, forward or back, never
// sideways. The moves' geometry is checked for every heading, and the search on fits set by hand
// (no scan, no footprint test): a failure here names the search, not the stages before it.

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "../../../core/src/traversability/motion_primitives.h"
#include "../../../core/src/traversability/reachability_search.h"
#include "clearway/traversability/reachability.h"
#include "clearway/traversability/traversability_map.h"

namespace clearway {
namespace {

using detail::MotionPrimitive;
using detail::MotionPrimitives;

constexpr double kDegree = std::numbers::pi / 180.0;

// The angle between two directions taken as lines (modulo 180 deg).
double lineAngle(double a, double b) {
  const double difference = std::fmod(std::abs(a - b), std::numbers::pi);
  return std::min(difference, std::numbers::pi - difference);
}

double directionOf(const MotionPrimitive& move) {
  return std::atan2(double(move.dy), double(move.dx));
}

std::vector<double> headingsEveryDegree() {
  std::vector<double> yaws;
  for (int degrees = 0; degrees < 180; ++degrees)
    yaws.push_back(degrees * kDegree);
  return yaws;
}

TEST(MotionPrimitives, EveryHeadingDrivesForwardAndBackAlongItselfAndCanEdgeBothWays) {
  const std::vector<double> yaws = headingsEveryDegree();
  const MotionPrimitives primitives = detail::motionPrimitives(yaws);
  ASSERT_EQ(primitives.of_orientation.size(), yaws.size());
  for (std::size_t k = 0; k < yaws.size(); ++k) {
    const std::vector<int>& moves = primitives.of_orientation[k];
    ASSERT_FALSE(moves.empty()) << k << " deg";
    bool left = false, right = false, along = false;
    for (const int index : moves) {
      const MotionPrimitive& move = primitives.moves[std::size_t(index)];
      // Never sideways: within the slip of the heading's line.
      EXPECT_LE(lineAngle(directionOf(move), yaws[k]), detail::kMoveSlipRad + 1e-9)
          << k << " deg: move (" << move.dx << ", " << move.dy << ")";
      EXPECT_LE(std::max(std::abs(move.dx), std::abs(move.dy)), detail::kLongestMoveCells);
      // Back as well as forward.
      EXPECT_TRUE(std::any_of(moves.begin(), moves.end(),
                              [&](int other) {
                                const MotionPrimitive& back = primitives.moves[std::size_t(other)];
                                return back.dx == -move.dx && back.dy == -move.dy;
                              }))
          << k << " deg: no reverse of (" << move.dx << ", " << move.dy << ")";
      // Which side of the heading the forward one of the pair lies on.
      const double forward = std::cos(yaws[k]) * move.dx + std::sin(yaws[k]) * move.dy;
      const double side = std::cos(yaws[k]) * move.dy - std::sin(yaws[k]) * move.dx;
      if (forward <= 0) continue;
      if (std::abs(side) < 1e-9 * move.length) along = true;
      (side > 0 ? left : right) |= std::abs(side) >= 1e-9 * move.length;
    }
    // The robot can edge to either side as it drives (steering a little), so that it can leave a
    // place where it fits only in its own heading.
    EXPECT_TRUE(left && right) << k << " deg";
    if (k % 45 == 0) {
      EXPECT_TRUE(along) << k << " deg";
    }
  }
}

TEST(MotionPrimitives, AMoveCrossesTheCellsItsLinePassesThroughInOrder) {
  const MotionPrimitives primitives = detail::motionPrimitives(headingsEveryDegree());
  for (const MotionPrimitive& move : primitives.moves) {
    ASSERT_FALSE(move.crossed.empty());
    EXPECT_EQ(move.crossed.back().dx, move.dx);
    EXPECT_EQ(move.crossed.back().dy, move.dy);
    EXPECT_FALSE(move.crossed.back().tie);
    EXPECT_NEAR(move.length, std::hypot(double(move.dx), double(move.dy)), 1e-12);
    // The cell before the current one, or before the pair at a corner (a pair's second cell is
    // not a step of its own: the line goes on from the first).
    int previous_x = 0, previous_y = 0;
    int main_x = 0, main_y = 0;  // the last cell that is not a pair's second
    for (const MotionPrimitive::Crossed& crossed : move.crossed) {
      // The line passes within half a cell of the cell's centre across its major axis.
      const double along = std::abs(move.dx) >= std::abs(move.dy) ? double(crossed.dx) / move.dx
                                                                  : double(crossed.dy) / move.dy;
      const double minor_error = std::abs(move.dx) >= std::abs(move.dy)
                                     ? std::abs(along * move.dy - crossed.dy)
                                     : std::abs(along * move.dx - crossed.dx);
      EXPECT_LE(minor_error, 0.5 + 1e-12) << move.dx << ", " << move.dy;
      if (!crossed.tie) {
        previous_x = main_x;
        previous_y = main_y;
        main_x = crossed.dx;
        main_y = crossed.dy;
      }
      // One eight-neighbour step from the cell before (the pair's: a corner's cells share it).
      const int step_x = std::abs(crossed.dx - previous_x),
                step_y = std::abs(crossed.dy - previous_y);
      EXPECT_LE(std::max(step_x, step_y), 1) << move.dx << ", " << move.dy;
      EXPECT_DOUBLE_EQ(crossed.step, step_x && step_y ? std::numbers::sqrt2 : 1.0);
    }
  }
}

// A map of `size` x `size` cells, `orientations` uniform headings, where the box fits only in
// the poses `fits(column, row, yaw in deg)` says; the robot stands at `start` in heading 0.
TraversabilityMap searchedMap(int orientations, bool heading_known, int size,
                              const Eigen::Vector2i& start,
                              const std::function<bool(int, int, double)>& fits) {
  TraversabilityMap map;
  map.grid = MapGrid{0.05, Eigen::Vector2d::Zero(), size, size};
  for (int k = 0; k < orientations; ++k)
    map.yaws.push_back(std::numbers::pi * k / orientations);
  map.robot_orientation = 0;
  map.robot_heading_known = heading_known;
  const Eigen::Vector2d centre = map.grid.centre(start.x(), start.y());
  map.robot_pose = {centre.x(), centre.y(), 0.0};
  map.labels.assign(map.grid.cells(), std::uint8_t(CellLabel::kImpassable));
  std::vector<std::uint8_t> pose_fits(map.grid.cells() * map.yaws.size(),
                                      std::uint8_t(PoseFit::kBlocked));
  std::vector<std::uint8_t> fit_orientation(map.grid.cells(), kNoOrientation);
  for (int row = 0; row < size; ++row)
    for (int column = 0; column < size; ++column)
      for (int k = 0; k < orientations; ++k) {
        if (!fits(column, row, map.yaws[std::size_t(k)] / kDegree)) continue;
        const std::size_t cell = map.grid.index(column, row);
        pose_fits[cell * map.yaws.size() + std::size_t(k)] = std::uint8_t(PoseFit::kClear);
        map.labels[cell] = std::uint8_t(CellLabel::kTraversable);
        if (fit_orientation[cell] == kNoOrientation) fit_orientation[cell] = std::uint8_t(k);
      }
  detail::searchReachable(map, pose_fits, detail::cellsTheSearchMayEnter(map, fit_orientation));
  return map;
}

bool reached(const TraversabilityMap& map, int column, int row) {
  return map.reach[map.grid.index(column, row)] != 0;
}

// Both searches: a word of orientations per cell (12), and one pose at a time (over 64).
class HandBuiltSearch : public ::testing::TestWithParam<int> {};

TEST_P(HandBuiltSearch, TheBoxIsNeverSlidSidewaysAlongAStripItFitsAcross) {
  // A strip one cell wide along y where the box fits only across it (heading 0, along x): the
  // robot standing in it cannot drive along it. The eight-neighbour moves of before slid it.
  const Eigen::Vector2i start{15, 10};
  auto acrossOnly = [](int column, int row, double yaw) {
    return column == 15 && row >= 5 && row <= 25 && std::abs(yaw) < 1e-9;
  };
  const TraversabilityMap map = searchedMap(GetParam(), true, 30, start, acrossOnly);
  EXPECT_TRUE(reached(map, 15, 10));
  EXPECT_EQ(map.reachable_cells, 1U);
  EXPECT_FALSE(reached(map, 15, 11));
  EXPECT_FALSE(reached(map, 15, 25));
  const Eigen::Vector2d far_end = map.grid.centre(15, 25);
  const GoalResult goal = planPath(map, far_end.x(), far_end.y());
  EXPECT_FALSE(goal.reachable);
  EXPECT_NE(goal.reason.find("cannot get there"), std::string::npos) << goal.reason;
}

TEST_P(HandBuiltSearch, TurnedAlongTheStripTheRobotDrivesItsLength) {
  // The box also fits along the strip (heading 90) and, at the robot's cell, in every heading:
  // it turns on the spot and drives to either end.
  const Eigen::Vector2i start{15, 10};
  auto alongOrTurning = [](int column, int row, double yaw) {
    if (column != 15 || row < 5 || row > 25) return false;
    return row == 10 || std::abs(yaw - 90.0) < 1e-9;
  };
  const TraversabilityMap map = searchedMap(GetParam(), true, 30, start, alongOrTurning);
  EXPECT_EQ(map.reachable_cells, 21U);
  const Eigen::Vector2d far_end = map.grid.centre(15, 25);
  const GoalResult goal = planPath(map, far_end.x(), far_end.y());
  ASSERT_TRUE(goal.reachable) << goal.reason;
  EXPECT_NEAR(goal.length_m, 15 * 0.05, 1e-9);
  EXPECT_NEAR(goal.path.back().heading_deg, 90.0, 1e-9);
}

TEST_P(HandBuiltSearch, AGuessedHeadingStartsFromEveryOrientationTheBoxFitsInAtItsPlace) {
  // At the robot's cell the box fits at 0 and 90 deg only (no turn between them); the strip is
  // driven at 90. With the heading recorded as 0, the robot stays; guessed, it may stand at 90.
  const Eigen::Vector2i start{15, 10};
  auto twoHeadings = [](int column, int row, double yaw) {
    if (column != 15 || row < 5 || row > 25) return false;
    return std::abs(yaw - 90.0) < 1e-9 || (row == 10 && std::abs(yaw) < 1e-9);
  };
  const TraversabilityMap known = searchedMap(GetParam(), true, 30, start, twoHeadings);
  EXPECT_EQ(known.reachable_cells, 1U);
  const TraversabilityMap guessed = searchedMap(GetParam(), false, 30, start, twoHeadings);
  EXPECT_EQ(guessed.reachable_cells, 21U);
  const Eigen::Vector2d far_end = guessed.grid.centre(15, 25);
  EXPECT_TRUE(planPath(guessed, far_end.x(), far_end.y()).reachable);
  EXPECT_FALSE(planPath(known, far_end.x(), far_end.y()).reachable);
}

TEST_P(HandBuiltSearch, TheRobotEdgesSidewaysWhereItHasRoomToDriveAlongItsHeading) {
  // Only heading 0 fits, in a band 20 cells long and 4 wide: the robot cannot turn, but steering
  // a little as it drives forward and back it reaches every row of the band.
  const Eigen::Vector2i start{15, 10};
  auto band = [](int column, int row, double yaw) {
    return column >= 5 && column < 25 && row >= 10 && row < 14 && std::abs(yaw) < 1e-9;
  };
  const TraversabilityMap map = searchedMap(GetParam(), true, 30, start, band);
  for (int row = 10; row < 14; ++row)
    EXPECT_TRUE(reached(map, 15, row)) << row;
}

INSTANTIATE_TEST_SUITE_P(Searches, HandBuiltSearch, ::testing::Values(12, 72),
                         [](const ::testing::TestParamInfo<int>& param_info) {
                           return std::to_string(param_info.param) + "_orientations";
                         });

}  // namespace
}  // namespace clearway
