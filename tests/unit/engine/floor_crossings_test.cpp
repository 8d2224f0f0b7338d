// Where beams went down through the floor's level over unobserved ground, no floor stood there
// (core/src/segmentation/floor_crossings.h). A lost return keeps its place in its fan, so its
// beam's direction is known: a RoSi beside a platform's edge with nothing below it sees the drop
// blocked and named, its guessed place keeps off it, and echoes lost now and then on the floor are
// no drop. A return from under the floor passed its level on the way: a trench's unseen near side.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "../../../core/src/segmentation/floor_crossings.h"
#include "engine_fixtures.h"

namespace clearway {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

constexpr double kBackWallX = -4.75;  // the wall's face [m]

// A slab 6 m wide from x = low_x to high_x whose top is the floor (z = 0).
sim::Primitive floorSlab(const std::string& name, double low_x, double high_x, double thickness) {
  sim::Primitive slab;
  slab.name = name;
  slab.point_class = PointClass::kGround;
  slab.center = {(low_x + high_x) / 2, 0.0, -thickness / 2};
  slab.size = {high_x - low_x, 6.0, thickness};
  return slab;
}

// A scene of floor slabs, a wall at their back.
sim::Scene sceneOf(const std::string& name, const std::vector<sim::Primitive>& slabs) {
  sim::Scene scene;
  scene.name = name;
  scene.primitives = slabs;
  sim::Primitive wall;
  wall.name = "back_wall";
  wall.point_class = PointClass::kWall;
  wall.center = {kBackWallX - 0.1, 0.0, 1.5};
  wall.size = {0.2, 6.0, 3.0};
  scene.primitives.push_back(wall);
  return scene;
}

// A platform whose top is the floor from the back wall to x = edge_x, and nothing beyond the edge:
// beams over it come back with nothing.
sim::Scene ledgeScene(double edge_x) {
  return sceneOf("ledge", {floorSlab("platform", kBackWallX, edge_x, 0.1)});
}

SegmentationParams smallRobot() {
  SegmentationParams params;
  params.robot.width = 0.6;
  params.robot.length = 0.8;
  return params;
}

Eigen::Isometry3d worldFromMap(const test::SimulatedRun& run) {
  return run.simulated.truth.placement.worldFromScanner() *
         run.result.analysis->map_from_scanner.inverse();
}

// The map shows a drop at the world positions (x, y, 0): impassable, "too steep".
void expectDropsAt(const test::SimulatedRun& run, const std::vector<double>& xs,
                   const std::vector<double>& ys) {
  const TraversabilityMap& map = run.result.map;
  const Eigen::Isometry3d map_from_world = worldFromMap(run).inverse();
  for (const double x : xs)
    for (const double y : ys) {
      SCOPED_TRACE(testing::Message() << x << ", " << y);
      const Eigen::Vector3d m = map_from_world * Eigen::Vector3d(x, y, 0.0);
      const Eigen::Vector2i cell = map.grid.cellOf(m.x(), m.y());
      ASSERT_TRUE(map.grid.inside(cell.x(), cell.y()));
      EXPECT_EQ(map.label(cell.x(), cell.y()), CellLabel::kImpassable);
      EXPECT_EQ(CellReason(map.reasons[map.grid.index(cell.x(), cell.y())]), CellReason::kTooSteep);
    }
}

TEST(LostBeams, TheRobotsGuessedPlaceKeepsOffADropBesideTheScanner) {
  // The scanner (its turntable axis along x, so it sees the half towards the edge) 0.3-0.45 m
  // from the edge. Unobserved, the cells over the drop were taken for floor the robot's body hid:
  // its box overhung the edge and the map showed it there (4 false cells at 0.3 and 0.45 m).
  const SegmentationParams params = smallRobot();
  for (const double edge_x : {0.3, 0.45}) {
    SCOPED_TRACE(edge_x);
    const test::SimulatedRun run = test::simulateFromOrigin(ledgeScene(edge_x), params);
    ASSERT_TRUE(run.result.trusted()) << run.result.reason;
    ASSERT_FALSE(run.result.analysis->inputs.floor_crossings.empty());
    EXPECT_EQ(test::evaluateRun(run, params).map.false_traversable_cells, 0U);
    const RobotPose& pose = run.result.map.robot_pose;
    const Eigen::Rotation2Dd turn(pose.yaw);
    for (const double u : {-0.5, 0.5})
      for (const double v : {-0.5, 0.5}) {
        const Eigen::Vector2d corner =
            Eigen::Vector2d(pose.x, pose.y) +
            turn * Eigen::Vector2d(u * params.robot.length, v * params.robot.width);
        const Eigen::Vector3d world =
            worldFromMap(run) * Eigen::Vector3d(corner.x(), corner.y(), 0);
        // The guess scores the box at samples a cell apart, half a cell in from its sides: a
        // corner may reach half a cell and a half diagonal past the last sample.
        const double sampling = run.result.map.grid.resolution * (0.5 + std::sqrt(0.5));
        EXPECT_LE(world.x(), edge_x + sampling) << "the robot's box overhangs the drop";
      }
  }
}

TEST(LostBeams, ADropIsBlockedAndNamedAsOne) {
  const double edge_x = 0.3;
  const SegmentationParams params = smallRobot();
  const test::SimulatedRun run = test::simulateFromOrigin(ledgeScene(edge_x), params);
  ASSERT_TRUE(run.result.trusted()) << run.result.reason;
  // Within the 20 deg of the scanner's foot where a floor sends a beam back (1 m up: 2.7 m).
  expectDropsAt(run, {edge_x + 0.2, edge_x + 0.8, edge_x + 1.5}, {-0.8, 0.0, 0.8});
}

TEST(LostBeams, EchoesLostNowAndThenOnTheFloorAreNoDrop) {
  // The platform's edge 6 m away, beyond the beams steep enough to vouch for a floor: a third of
  // the returns lost at random, on the floor among the rest, and no crossing anywhere. The axes
  // turn the fans' ends down to the floor (where a run has no return beyond it). With runs of 6
  // to a line's end taken for a drop, the third axis (200 lines, seed 2) made 7 crossings.
  const SegmentationParams params = smallRobot();
  for (const Eigen::Vector3d& axis :
       {Eigen::Vector3d(1.0, 0.0, 0.0), Eigen::Vector3d(1.0, 0.0, -1.0),
        Eigen::Vector3d(1.0, 0.3, 0.2)}) {
    sim::SensorModel sensor;
    sensor.lines = 200;
    sensor.dropout = 0.3;
    sensor.seed = 2;
    sim::ScannerPlacement placement;
    placement.position = {0.0, 0.0, 1.0};
    placement.axis = axis;
    SCOPED_TRACE(testing::Message() << axis.transpose());
    const test::SimulatedRun run =
        test::simulateSavedAndSegment(ledgeScene(6.0), sensor, placement, params);
    ASSERT_TRUE(run.result.trusted()) << run.result.reason;
    EXPECT_TRUE(run.result.analysis->inputs.floor_crossings.empty());
    EXPECT_EQ(test::evaluateRun(run, params).map.false_traversable_cells, 0U);
  }
}

// One fan of a scanner 1 m above the floor, turning about y from straight down towards +x by 1 deg
// a beam, half a step off: beam k points (k + 0.5) deg from straight down and meets the floor at
// x = tan((k + 0.5) deg).
Eigen::Vector3d beamOf(int k) {
  const double angle = (k + 0.5) * kDeg;
  return {std::sin(angle), 0.0, -std::cos(angle)};
}

double floorX(int k) {
  return std::tan((k + 0.5) * kDeg);
}

// The fan's returns on the floor; `lost` beams came back with nothing.
Scan fanOverFloor(const std::vector<int>& lost) {
  Scan scan;
  constexpr int kBeams = 80;
  for (int k = 0; k < kBeams; ++k) {
    const bool is_lost = std::find(lost.begin(), lost.end(), k) != lost.end();
    const Eigen::Vector3d point = beamOf(k) / -beamOf(k).z();  // on z = -1
    scan.points.push_back(is_lost ? Point3f{NAN, NAN, NAN}
                                  : Point3f{float(point.x()), float(point.y()), float(point.z())});
    scan.status.push_back(is_lost ? PointStatus::kNoReturn : PointStatus::kValid);
  }
  scan.lines.push_back({0, std::size_t(kBeams), 0.0});
  return scan;
}

// The hand-made scans' scanner 1 m above the map's origin, over a 6 x 6 m grid of 5 cm cells where
// no ground was seen.
Eigen::Isometry3d scannerOneMetreUp() {
  Eigen::Isometry3d map_from_scanner = Eigen::Isometry3d::Identity();
  map_from_scanner.translation() = Eigen::Vector3d(0.0, 0.0, 1.0);
  return map_from_scanner;
}

MapGrid sixMetresSquare() {
  MapGrid grid;
  grid.resolution = 0.05;
  grid.origin = {-3.0, -3.0};
  grid.width = grid.height = 120;
  return grid;
}

std::vector<FloorCrossing> crossingsOf(const Scan& scan, MapGrid* grid_out = nullptr,
                                       double sensor_step = 1.0 * kDeg) {
  SensorGeometry sensor;
  sensor.kind = SensorKind::kRotating2D;
  sensor.along_line_step = sensor_step;
  sensor.lines = 1;
  const MapGrid grid = sixMetresSquare();
  if (grid_out) *grid_out = grid;
  const std::vector<std::int16_t> unobserved(grid.cells(), -1);
  return detail::lostBeamCrossings(scan, sensor, scannerOneMetreUp(), grid, unobserved);
}

TEST(LostBeams, ALostBeamCrossesTheFloorWhereItsFanPointed) {
  // Beams 50-79 lost to the line's end: the fan continued from the returns before them. Those at
  // least 20 deg below the horizontal (k <= 69) cross the floor where their returns would be.
  std::vector<int> lost;
  for (int k = 50; k < 80; ++k)
    lost.push_back(k);
  MapGrid grid;
  const std::vector<FloorCrossing> crossings = crossingsOf(fanOverFloor(lost), &grid);
  ASSERT_EQ(crossings.size(), 20U);
  for (std::size_t i = 0; i < crossings.size(); ++i) {
    EXPECT_NEAR(crossings[i].x, floorX(50 + int(i)), 1e-4) << "beam " << 50 + i;
    EXPECT_NEAR(crossings[i].y, 0.0, 1e-6);
    const Eigen::Vector2i cell = grid.cellOf(crossings[i].x, crossings[i].y);
    EXPECT_EQ(crossings[i].cell, grid.index(cell.x(), cell.y()));
  }
  // The same run reached from the other end: the fan read backwards from the returns after it.
  std::vector<int> first_lost;
  for (int k = 0; k < 10; ++k)
    first_lost.push_back(k);
  const std::vector<FloorCrossing> from_after = crossingsOf(fanOverFloor(first_lost));
  ASSERT_EQ(from_after.size(), 10U);
  for (std::size_t i = 0; i < from_after.size(); ++i)
    EXPECT_NEAR(from_after[i].x, floorX(int(i)), 1e-4) << "beam " << i;
}

TEST(LostBeams, AShortRunBetweenTwoFloorReturnsIsNoDrop) {
  // Lost between returns on the floor, or at the line's end, only as many in a row as lost echoes
  // make: echoes lost on a floor, not where it ends.
  EXPECT_TRUE(crossingsOf(fanOverFloor({20, 21, 22, 23, 24, 25, 26, 27, 28})).empty());
  EXPECT_TRUE(crossingsOf(fanOverFloor({0, 1, 2, 3, 4, 5, 6, 7, 8})).empty());
  // Ten in a row are more than lost echoes make: a pit whose far side was seen, or the floor's end.
  EXPECT_EQ(crossingsOf(fanOverFloor({20, 21, 22, 23, 24, 25, 26, 27, 28, 29})).size(), 10U);
  EXPECT_EQ(crossingsOf(fanOverFloor({0, 1, 2, 3, 4, 5, 6, 7, 8, 9})).size(), 10U);
  // Followed by a return on a wall: not where the floor ends either.
  Scan wall = fanOverFloor({30, 31, 32, 33});
  const Eigen::Vector3d on_wall = beamOf(34) * 0.6;  // 0.4 m above the floor
  wall.points[34] = {float(on_wall.x()), float(on_wall.y()), float(on_wall.z())};
  EXPECT_TRUE(crossingsOf(wall).empty());
  // Followed by a return far under the floor's level (a drop's bottom): the run is a drop.
  Scan pit = fanOverFloor({30, 31, 32});
  const Eigen::Vector3d bottom = beamOf(33) * (2.0 / -beamOf(33).z());  // 1 m under the floor
  pit.points[33] = {float(bottom.x()), float(bottom.y()), float(bottom.z())};
  EXPECT_EQ(crossingsOf(pit).size(), 3U);
}

TEST(LostBeams, NoDirectionIsGuessedWhereTheReturnsAroundARunDoNotTurnByTheStep) {
  // The return after the run lies 15.5 deg back from the one before it, where the fan would have
  // turned 6 deg on: not one fan, so no crossing is claimed (it lies well under the floor, so the
  // run would otherwise be a drop).
  Scan scan = fanOverFloor({41, 42, 43, 44, 45});
  const Eigen::Vector3d elsewhere = Eigen::Vector3d(std::sin(25 * kDeg), 0.0, -std::cos(25 * kDeg));
  const Eigen::Vector3d far = elsewhere * 3.0;
  scan.points[46] = {float(far.x()), float(far.y()), float(far.z())};
  EXPECT_TRUE(crossingsOf(scan).empty());
  // The same return where the fan pointed: the run's beams cross the floor.
  const Eigen::Vector3d along = beamOf(46) * 3.0;
  scan.points[46] = {float(along.x()), float(along.y()), float(along.z())};
  EXPECT_EQ(crossingsOf(scan).size(), 5U);
  // A sensor whose step is not known (0, NaN) gives no direction to check against.
  EXPECT_TRUE(crossingsOf(scan, nullptr, 0.0).empty());
  EXPECT_TRUE(crossingsOf(scan, nullptr, std::numeric_limits<double>::quiet_NaN()).empty());
}

// Returns from well under the floor: their beams passed the floor's level on the way down.

std::vector<FloorCrossing> crossingsUnderFloorOf(const std::vector<MapObstacle>& obstacles) {
  const MapGrid grid = sixMetresSquare();
  const std::vector<std::int16_t> unobserved(grid.cells(), -1);
  return detail::crossingsOfReturnsUnderFloor(obstacles, scannerOneMetreUp(), grid, unobserved);
}

MapObstacle obstacleAt(float x, float y, float z) {
  MapObstacle o;
  o.x = x;
  o.y = y;
  o.z = z;
  return o;
}

TEST(ReturnsUnderTheFloor, CrossTheFloorsLevelOnTheirBeam) {
  // The scanner 1 m up: a return 1 m under the floor 2 m out crossed the floor's level 1 m out.
  const std::vector<FloorCrossing> crossings =
      crossingsUnderFloorOf({obstacleAt(2.0F, 0.0F, -1.0F), obstacleAt(0.0F, -1.0F, -1.0F)});
  ASSERT_EQ(crossings.size(), 2U);
  EXPECT_NEAR(crossings[0].x, 1.0, 1e-6);
  EXPECT_NEAR(crossings[0].y, 0.0, 1e-6);
  EXPECT_NEAR(crossings[1].x, 0.0, 1e-6);
  EXPECT_NEAR(crossings[1].y, -0.5, 1e-6);
  // Within the floor's noise and a low step under it, or seen too flat to say where the floor
  // ended (the reference plane only approximates uneven ground out there): none.
  EXPECT_TRUE(crossingsUnderFloorOf({obstacleAt(2.0F, 0.0F, -0.15F)}).empty());
  EXPECT_TRUE(crossingsUnderFloorOf({obstacleAt(5.0F, 0.0F, -0.3F)}).empty());
}

TEST(ReturnsUnderTheFloor, TheNearSideOfATrenchWhoseFarWallWasSeenIsADrop) {
  // A trench 2 m deep from x = 1.2 to 2.2 m across the floor: its near wall faces away from the
  // scanner and is never seen, its far wall is. The beams that met the far wall passed the
  // floor's level over the trench's near half: those cells were unknown, and are now a drop.
  const sim::Scene scene = sceneOf("trench", {floorSlab("near_floor", kBackWallX, 1.2, 2.0),
                                              floorSlab("far_floor", 2.2, 6.0, 2.0)});
  const SegmentationParams params = smallRobot();
  const test::SimulatedRun run = test::simulateFromOrigin(scene, params);
  ASSERT_TRUE(run.result.trusted()) << run.result.reason;
  EXPECT_EQ(test::evaluateRun(run, params).map.false_traversable_cells, 0U);
  expectDropsAt(run, {1.25, 1.35}, {-0.5, 0.0, 0.5});
}

}  // namespace
}  // namespace clearway
