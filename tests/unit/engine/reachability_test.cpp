// The robot's own place and "Can it get there?": the robot stands on its own cells, and cells it
// fits in but cannot get to are told apart from the reachable ones.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <string>
#include <utility>
#include <vector>

#include "../../../core/src/traversability/motion_primitives.h"
#include "../../../core/src/traversability/reachability_search.h"
#include "clearway/io/scan_io.h"
#include "clearway/pose.h"
#include "clearway/sim/builtin_scenes.h"
#include "engine_fixtures.h"
#include "test_support.h"

namespace clearway {
namespace {

const Eigen::Vector3d kYard{6.5, -1.0, 0.0};  // outside the garage's 0.9 m door (world frame)

SegmentationParams robotOfWidth(double width) {
  SegmentationParams params;
  params.robot.width = width;
  return params;
}

Eigen::Vector2d mapPosition(const test::SimulatedRun& run, const Eigen::Vector3d& world) {
  const Eigen::Isometry3d map_from_world =
      run.result.analysis->map_from_scanner *
      run.simulated.truth.placement.worldFromScanner().inverse();
  return (map_from_world * world).head<2>();
}

bool reachableAt(const TraversabilityMap& map, const Eigen::Vector2d& position) {
  const Eigen::Vector2i cell = map.grid.cellOf(position.x(), position.y());
  return map.grid.inside(cell.x(), cell.y()) && map.reach[map.grid.index(cell.x(), cell.y())];
}

void expectOwnPlaceReachable(const TraversabilityMap& map) {
  const Eigen::Vector2d robot(map.robot_pose.x, map.robot_pose.y);
  EXPECT_TRUE(reachableAt(map, robot));
  EXPECT_GT(map.reachable_cells, 0U);
}

class OwnPlace : public ::testing::TestWithParam<std::string> {};

TEST_P(OwnPlace, TheRobotsOwnCellsAreReachable) {
  const auto run = test::simulateAndSegment(GetParam(), 200);
  ASSERT_TRUE(run.result.trusted()) << run.result.reason;
  expectOwnPlaceReachable(run.result.map);
}

std::vector<std::string> scenesWithGround() {
  std::vector<std::string> names;
  for (const std::string& name : sim::builtinSceneNames())
    if (name != "no-ground") names.push_back(name);
  return names;
}

INSTANTIATE_TEST_SUITE_P(Scenes, OwnPlace, ::testing::ValuesIn(scenesWithGround()));

TEST(OwnPlace, TheRobotStandsOnItsOwnCellsInTheRealRoomScan) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, "pcl-room/room_scan1.pcd");
  Scan scan = loadScan(file);
  resolveScanPose(scan, {});
  const PipelineResult result = runPipeline(scan, SegmentationParams{});
  ASSERT_TRUE(result.trusted()) << result.reason;
  expectOwnPlaceReachable(result.map);
  // The robot's own cells are no longer an unknown or blocked blob: they are floor.
  const TraversabilityMap& map = result.map;
  const Eigen::Vector2i cell = map.grid.cellOf(map.robot_pose.x, map.robot_pose.y);
  EXPECT_NE(map.label(cell.x(), cell.y()), CellLabel::kUnknown);
}

TEST(Reachability, TheYardFitsButCannotBeReachedThroughADoorTooNarrow) {
  const auto run = test::simulateAndSegment("garage", 423, robotOfWidth(0.95));
  ASSERT_TRUE(run.result.trusted());
  const TraversabilityMap& map = run.result.map;
  // Every cell of the yard (beyond the door, world x > 4.6) where the robot fits: none reachable.
  const Eigen::Isometry3d map_from_world =
      run.result.analysis->map_from_scanner *
      run.simulated.truth.placement.worldFromScanner().inverse();
  const Eigen::Isometry3d world_from_map = map_from_world.inverse();
  int yard_fits = 0, yard_reachable = 0;
  Eigen::Vector2d yard(0.0, 0.0);
  for (int row = 0; row < map.grid.height; ++row)
    for (int column = 0; column < map.grid.width; ++column) {
      const Eigen::Vector2d centre = map.grid.centre(column, row);
      const Eigen::Vector3d world = world_from_map * Eigen::Vector3d(centre.x(), centre.y(), 0.0);
      const CellLabel label = map.label(column, row);
      if (world.x() < 4.6 || (label != CellLabel::kTraversable && label != CellLabel::kCareful))
        continue;
      ++yard_fits;
      yard = centre;
      yard_reachable += map.reach[map.grid.index(column, row)];
    }
  EXPECT_GT(yard_fits, 100) << "the 0.95 m robot fits in the yard";
  EXPECT_EQ(yard_reachable, 0);
  EXPECT_GE(map.fits_not_reachable_cells, std::size_t(yard_fits));
  const GoalResult goal = planPath(map, yard.x(), yard.y());
  EXPECT_FALSE(goal.reachable);
  EXPECT_NE(goal.reason.find("cannot get there"), std::string::npos) << goal.reason;
}

TEST(Reachability, TheSmallRobotGetsAPathThroughTheDoor) {
  const auto run = test::simulateAndSegment("garage", 423, robotOfWidth(0.85));
  ASSERT_TRUE(run.result.trusted());
  const TraversabilityMap& map = run.result.map;
  const Eigen::Vector2d yard = mapPosition(run, kYard);
  ASSERT_TRUE(reachableAt(map, yard));
  const GoalResult goal = planPath(map, yard.x(), yard.y());
  ASSERT_TRUE(goal.reachable) << goal.reason;
  ASSERT_GE(goal.path.size(), 2U);
  // From the robot's pose to the goal's cell, through reachable cells only.
  EXPECT_NEAR(goal.path.front().x, map.robot_pose.x, map.grid.resolution);
  EXPECT_NEAR(goal.path.front().y, map.robot_pose.y, map.grid.resolution);
  EXPECT_NEAR(goal.path.back().x, yard.x(), map.grid.resolution);
  EXPECT_NEAR(goal.path.back().y, yard.y(), map.grid.resolution);
  for (const PathPose& pose : goal.path)
    EXPECT_TRUE(reachableAt(map, {pose.x, pose.y})) << pose.x << ", " << pose.y;
  const double straight = std::hypot(yard.x() - map.robot_pose.x, yard.y() - map.robot_pose.y);
  EXPECT_GE(goal.length_m, straight - map.grid.resolution);
  // Through the 0.9 m door, the robot must be square to the wall: some pose on the way is.
  const Eigen::Vector2d door = mapPosition(run, {4.1, -1.0, 0.0});
  double nearest = 1e9;
  for (const PathPose& pose : goal.path)
    nearest = std::min(nearest, std::hypot(pose.x - door.x(), pose.y - door.y()));
  EXPECT_LT(nearest, 0.6) << "the path leaves through the door";
}

// A robot wider than the 0.9 m door but shorter than it fits in the yard, and would pass the door
// sideways; a tracked or wheeled base does not slide. The search of before took it through
// ("Can it get there? Yes"); a robot narrower than the door still gets through, square to it.
TEST(Reachability, ARobotWiderThanTheDoorIsNotTakenThroughItSideways) {
  for (const double width : {0.92, 0.86}) {
    SegmentationParams params = robotOfWidth(width);
    params.robot.length = 0.5;
    const auto run = test::simulateAndSegment("garage", 423, params);
    ASSERT_TRUE(run.result.trusted());
    const TraversabilityMap& map = run.result.map;
    const Eigen::Vector2d yard = mapPosition(run, kYard);
    const Eigen::Vector2i cell = map.grid.cellOf(yard.x(), yard.y());
    ASSERT_TRUE(map.grid.inside(cell.x(), cell.y()));
    ASSERT_TRUE(robotFits(map.label(cell.x(), cell.y()))) << width << " m";
    const GoalResult goal = planPath(map, yard.x(), yard.y());
    if (width > 0.9) {
      EXPECT_FALSE(goal.reachable) << width << " m";
      EXPECT_NE(goal.reason.find("cannot get there"), std::string::npos) << goal.reason;
    } else {
      EXPECT_TRUE(goal.reachable) << width << " m: " << goal.reason;
    }
  }
}

// The cheapest cost from the robot's pose to any pose in `goal`'s cell, by a plain Dijkstra over
// every (cell, orientation) state of the reachable cells: the definition planPath's A* must meet
// whatever its heuristic. Costs as docs/ALGORITHM.md gives them: a move costs each cell it
// crosses as a single step into it would (1 or sqrt 2 cells), three times that on orange, and
// 0.05 m per turn step.
double cheapestCost(const TraversabilityMap& map, const Eigen::Vector2d& goal) {
  constexpr double kCarefulFactor = 3.0, kTurnStep = 0.05;
  const MapGrid& grid = map.grid;
  const std::size_t orientations = map.yaws.size();
  const auto turns = detail::turnNeighbours(map.yaws);
  const detail::MotionPrimitives moves = detail::motionPrimitives(map.yaws);
  std::vector<double> cost(grid.cells() * orientations, std::numeric_limits<double>::infinity());
  using Entry = std::pair<double, std::size_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  auto factor = [&](std::size_t state) {
    if (!map.reach[state / orientations]) return 0.0;
    const PoseFit fit = map.pose_fit.at(state / orientations, state % orientations);
    return fit == PoseFit::kClear ? 1.0 : fit == PoseFit::kCareful ? kCarefulFactor : 0.0;
  };
  // From the robot's own pose; with its heading a guess, from any orientation that fits there.
  const Eigen::Vector2i start = grid.cellOf(map.robot_pose.x, map.robot_pose.y);
  for (std::size_t k = 0; k < orientations; ++k) {
    const std::size_t state = grid.index(start.x(), start.y()) * orientations + k;
    if (int(k) == map.robot_orientation || (!map.robot_heading_known && factor(state) > 0)) {
      cost[state] = 0.0;
      queue.push({0.0, state});
    }
  }
  const Eigen::Vector2i target = grid.cellOf(goal.x(), goal.y());
  const std::size_t goal_cell = grid.index(target.x(), target.y());
  while (!queue.empty()) {
    const auto [here, state] = queue.top();
    queue.pop();
    if (here > cost[state]) continue;
    const std::size_t cell = state / orientations;
    if (cell == goal_cell) return here;
    const int k = int(state % orientations);
    const int column = int(cell % std::size_t(grid.width)),
              row = int(cell / std::size_t(grid.width));
    auto relax = [&](std::size_t next, double added) {
      if (here + added >= cost[next]) return;
      cost[next] = here + added;
      queue.push({cost[next], next});
    };
    // A move: each cell it crosses costs the step into it as a single move would (1 or sqrt 2
    // cells) times its factor; past a corner's pair of cells, the dearer; ending in the pair's
    // second, its own step from the cell before the pair. It ends at the goal's cell.
    for (const int index : moves.of_orientation[std::size_t(k)]) {
      const auto& crossed_cells = moves.moves[std::size_t(index)].crossed;
      double going_on = 0.0, before_pair = 0.0;
      for (std::size_t i = 0; i < crossed_cells.size(); ++i) {
        const detail::MotionPrimitive::Crossed& crossed = crossed_cells[i];
        const int c = column + crossed.dx, r = row + crossed.dy;
        if (!grid.inside(c, r)) break;
        const std::size_t next = grid.index(c, r) * orientations + std::size_t(k);
        const double f = factor(next);
        if (f == 0.0) break;
        const double step = grid.resolution * crossed.step;
        double ending_here = 0.0;
        if (crossed.tie) {
          const double pair_step = grid.resolution * crossed_cells[i - 1].step;
          const detail::MotionPrimitive::Crossed& first = crossed_cells[i - 1];
          const double first_factor =
              factor(grid.index(column + first.dx, row + first.dy) * orientations + std::size_t(k));
          const double pair_factor = std::max(f, first_factor);
          going_on = before_pair + pair_step * pair_factor;
          ending_here = before_pair + step * f;
        } else {
          before_pair = going_on;
          going_on += step * f;
          ending_here = going_on;
        }
        if (grid.index(c, r) == goal_cell) {
          relax(next, ending_here);
          break;
        }
        if (i + 1 == crossed_cells.size()) relax(next, going_on);
      }
    }
    for (const int other : turns[std::size_t(k)])
      if (const double f = factor(cell * orientations + std::size_t(other)); f > 0.0)
        relax(cell * orientations + std::size_t(other), kTurnStep * f);
  }
  return std::numeric_limits<double>::infinity();
}

// The goal query's A* finds the cheapest path (its heuristic never overestimates), on scenes whose
// routes wind through doors, to the farthest reachable cell and to a spread of others.
TEST(Reachability, TheGoalQueryFindsTheCheapestPath) {
  for (const std::string scene : {"garage", "doorways"}) {
    const auto run = test::simulateAndSegment(scene, 200);
    ASSERT_TRUE(run.result.trusted()) << scene;
    const TraversabilityMap& map = run.result.map;
    std::vector<Eigen::Vector2d> goals;
    Eigen::Vector2d farthest(map.robot_pose.x, map.robot_pose.y);
    std::size_t seen = 0;
    for (int row = 0; row < map.grid.height; ++row)
      for (int column = 0; column < map.grid.width; ++column) {
        if (!map.reach[map.grid.index(column, row)]) continue;
        const Eigen::Vector2d centre = map.grid.centre(column, row);
        if ((centre - Eigen::Vector2d(map.robot_pose.x, map.robot_pose.y)).norm() >
            (farthest - Eigen::Vector2d(map.robot_pose.x, map.robot_pose.y)).norm())
          farthest = centre;
        if (++seen % 409 == 0) goals.push_back(centre);
      }
    goals.push_back(farthest);
    ASSERT_GE(goals.size(), 5U) << scene;
    for (const Eigen::Vector2d& goal : goals) {
      const GoalResult answer = planPath(map, goal.x(), goal.y());
      ASSERT_TRUE(answer.reachable) << scene << " " << goal.transpose() << ": " << answer.reason;
      EXPECT_NEAR(answer.cost, cheapestCost(map, goal), 1e-9) << scene << " " << goal.transpose();
    }
  }
}

TEST(Reachability, TheWideRobotIsToldWhy) {
  const auto run = test::simulateAndSegment("garage", 423, robotOfWidth(1.0));
  ASSERT_TRUE(run.result.trusted());
  const Eigen::Vector2d yard = mapPosition(run, kYard);
  const GoalResult goal = planPath(run.result.map, yard.x(), yard.y());
  EXPECT_FALSE(goal.reachable);
  EXPECT_FALSE(goal.reason.empty());
  EXPECT_TRUE(goal.path.empty());
}

TEST(Reachability, AGoalOutsideTheMapIsRefusedWithAReason) {
  const auto run = test::simulateAndSegment("garage", 200);
  const GoalResult goal = planPath(run.result.map, 1e4, 1e4);
  EXPECT_FALSE(goal.reachable);
  EXPECT_NE(goal.reason.find("outside the map"), std::string::npos);
}

TEST(OwnPlace, WithoutARecordedPoseTheRobotStandsWhereItFitsWithTheScannerOnIt) {
  // The garage's scanner stands 0.35 m from the back wall, which it never saw (it looks forward):
  // a robot centred under it would stand in that wall. It stands where it fits, the scanner on it.
  const auto run = test::simulateAndSegment("garage", 423);
  ASSERT_TRUE(run.result.trusted());
  const TraversabilityMap& map = run.result.map;
  const RobotPose& pose = map.robot_pose;
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  const double u = -pose.x * c - pose.y * s, v = pose.x * s - pose.y * c;  // the foot, robot frame
  EXPECT_LE(std::abs(u), 0.6 + 1e-9);
  EXPECT_LE(std::abs(v), 0.425 + 1e-9);
  expectOwnPlaceReachable(map);
  // ... and from there it gets around the garage.
  EXPECT_GT(map.reachable_cells, 1000U);
}

// Without a recorded pose the scanner's foot is put where the robot's box stands on its own level:
// not over the garage's 0.12 m pallet, whose top is ground of another level for a 0.1 m step. The
// scanner tilted 30 and 37 deg put the foot at the box's corner with the box over the pallet's
// top, and the robot's own place (ground, seen or not) showed 38 and 57 cells by the pallet's
// corner traversable where the box reaches into it (scripts/random-sweep).
TEST(OwnPlace, TheGuessedPlaceIsNotOverAnotherLevel) {
  SegmentationParams params;
  params.robot.width = 0.978;
  params.robot.length = 1.44;
  for (const double tilt : {-30.0, -37.03}) {
    const auto run = test::simulateAndSegment("garage", 350, params, tilt, -3.76);
    ASSERT_TRUE(run.result.trusted()) << tilt;
    EXPECT_EQ(test::evaluateRun(run, params).map.false_traversable_cells, 0u) << tilt;
    // No cell of an unreachable level lies under the box.
    const TraversabilityMap& map = run.result.map;
    const MapInputs& inputs = run.result.analysis->inputs;
    const RobotPose& pose = map.robot_pose;
    const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
    std::size_t other_level = 0;
    for (int row = 0; row < map.grid.height; ++row)
      for (int column = 0; column < map.grid.width; ++column) {
        const Eigen::Vector2d p = map.grid.centre(column, row) - Eigen::Vector2d(pose.x, pose.y);
        const double u = p.x() * c + p.y() * s, v = -p.x() * s + p.y() * c;
        if (std::abs(u) >= params.robot.length / 2 || std::abs(v) >= params.robot.width / 2)
          continue;
        const int plane = inputs.ground_plane[map.grid.index(column, row)];
        other_level += plane >= 0 &&
                       std::find(map.accepted_ground.begin(), map.accepted_ground.end(), plane) ==
                           map.accepted_ground.end();
      }
    EXPECT_EQ(other_level, 0u) << tilt;
    expectOwnPlaceReachable(map);
  }
}

}  // namespace
}  // namespace clearway
