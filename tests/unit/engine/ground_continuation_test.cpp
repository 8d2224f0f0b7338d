// Ground that no plane took in: a floor that rises gently in a small dome leaves its upper returns
// more than the planes' support band off the floor plane and in no plane of their own. They
// continue the floor's ground along and across the scan lines (docs/ALGORITHM.md, "Ground no plane
// took in"), while a low box's top, reached over its face, stays what it is.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "clearway/eval/evaluation.h"
#include "clearway/pipeline.h"
#include "clearway/sim/builtin_scenes.h"
#include "engine_fixtures.h"

namespace clearway {
namespace {

// A dome on the floor: too small and too curved for a plane of its own, and its top more than
// the support band above the floor's plane.
const Eigen::Vector2d kDomeCentre(2.5, 0.0);
constexpr double kDomeRadius = 0.8;  // [m]
constexpr double kColumn = 0.05;     // the dome is built of columns this wide [m]

double domeHeight(double x, double y, double peak) {
  const double r = (Eigen::Vector2d(x, y) - kDomeCentre).norm();
  if (r >= kDomeRadius) return 0.0;
  return peak * std::pow(std::cos(std::numbers::pi / 2 * r / kDomeRadius), 2);
}

sim::Primitive box(const std::string& name, PointClass point_class, Eigen::Vector3d min,
                   Eigen::Vector3d max) {
  sim::Primitive primitive;
  primitive.name = name;
  primitive.point_class = point_class;
  primitive.center = (min + max) / 2;
  primitive.size = max - min;
  return primitive;
}

// A RoSi 1 m above a floor with a dome `peak` high on it (smooth: columns 5 cm wide, each a few
// millimetres above the next), and, when `box_height` > 0, a box that high beside it.
test::SimulatedRun domeScene(double peak, double box_height = 0.0) {
  sim::Scene scene;
  scene.name = "dome";
  scene.primitives.push_back(
      box("floor", PointClass::kGround, {-6.0, -6.0, -1.0}, {8.0, 6.0, 0.0}));
  int column = 0;
  for (double x = kDomeCentre.x() - kDomeRadius; x < kDomeCentre.x() + kDomeRadius; x += kColumn)
    for (double y = kDomeCentre.y() - kDomeRadius; y < kDomeCentre.y() + kDomeRadius;
         y += kColumn) {
      const double height = domeHeight(x + kColumn / 2, y + kColumn / 2, peak);
      if (height < 0.002) continue;
      scene.primitives.push_back(box("dome_" + std::to_string(column++), PointClass::kGround,
                                     {x, y, -0.5}, {x + kColumn, y + kColumn, height}));
    }
  if (box_height > 0)
    scene.primitives.push_back(
        box("box", PointClass::kObstacle, {1.5, 1.0, 0.0}, {2.0, 1.5, box_height}));
  return test::simulateFromOrigin(scene, SegmentationParams{});
}

bool shownTraversable(CellLabel label) {
  return label == CellLabel::kTraversable || label == CellLabel::kCareful;
}

TEST(GroundContinuation, AGentleDomeOffTheFloorPlaneIsGround) {
  // Its top 9 cm up, over the planes' 5 cm support band; its flanks rise at most 10 deg.
  const double peak = 0.09;
  const test::SimulatedRun run = domeScene(peak);
  ASSERT_TRUE(run.result.trusted()) << run.result.reason;
  for (const Eigen::Vector2d& offset :
       {Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(0.15, 0.1), Eigen::Vector2d(-0.1, -0.2)}) {
    const Eigen::Vector2d p = kDomeCentre + offset;
    SCOPED_TRACE(p.transpose());
    EXPECT_TRUE(
        shownTraversable(test::labelAtWorld(run, {p.x(), p.y(), domeHeight(p.x(), p.y(), peak)})));
  }
}

TEST(GroundContinuation, ALowBoxTopIsNotGround) {
  // 8 cm: under the robot's step, yet not ground: its top is reached over its face, a rise no
  // ground makes from one return to the next. Continued, it would be green.
  const test::SimulatedRun run = domeScene(0.09, 0.08);
  ASSERT_TRUE(run.result.trusted()) << run.result.reason;
  for (const Eigen::Vector3d& on_top :
       {Eigen::Vector3d(1.75, 1.25, 0.08), Eigen::Vector3d(1.6, 1.4, 0.08),
        Eigen::Vector3d(1.9, 1.1, 0.08)}) {
    SCOPED_TRACE(on_top.transpose());
    EXPECT_FALSE(shownTraversable(test::labelAtWorld(run, on_top)));
  }
}

// A gutter across the floor, `depth` deep: its bottom 0.1 m wide, its sides sloping down over
// 0.05 m (columns 2.5 cm wide), `centre_x` from the foot of a RoSi 1 m up with `lines` lines.
test::SimulatedRun gutterScene(double depth, double centre_x, int lines) {
  constexpr double kBottom = 0.05, kSide = 0.05, kStep = 0.025;  // half the bottom, a side [m]
  sim::Scene scene;
  scene.name = "gutter";
  const double left = centre_x - kBottom - kSide, right = centre_x + kBottom + kSide;
  scene.primitives.push_back(
      box("floor", PointClass::kGround, {-6.0, -6.0, -1.0}, {left, 6.0, 0.0}));
  scene.primitives.push_back(
      box("floor", PointClass::kGround, {right, -6.0, -1.0}, {8.0, 6.0, 0.0}));
  int column = 0;
  for (double x = left; x < right - 1e-9; x += kStep) {
    const double off_centre = std::abs(x + kStep / 2 - centre_x);
    const double below =
        off_centre <= kBottom ? depth : depth * (kBottom + kSide - off_centre) / kSide;
    scene.primitives.push_back(box("gutter_" + std::to_string(column++), PointClass::kGround,
                                   {x, -6.0, -1.0}, {x + kStep, 6.0, -below}));
  }
  sim::SensorModel sensor;
  sensor.lines = lines;
  sensor.max_range = 8.0;
  sim::ScannerPlacement placement;
  placement.position = {0.0, 0.0, 1.0};
  placement.axis = {1.0, 0.0, 0.0};
  return test::simulateSavedAndSegment(scene, sensor, placement);
}

// A gutter 0.2 m deep, twice the robot's step, its bottom hidden from the scanner by its near
// rim: the beams pass over it onto its far side, whose upper 5 cm lie in the floor plane's band.
// Nothing seen says how deep it is, so it must not be shown drivable. (Letting ground continue
// down into a dip by up to a step, as a drain channel's 6-8 cm on Hannover's paving would want,
// took the far side's lower returns in and joined the floor across this gutter: kept out.)
TEST(GroundContinuation, AGutterDeeperThanTheStepIsNotShownDrivable) {
  const test::SimulatedRun deep = gutterScene(0.2, 2.5, 100);
  ASSERT_TRUE(deep.result.trusted()) << deep.result.reason;
  for (const double y : {-1.0, 0.0, 0.8}) {
    SCOPED_TRACE(y);
    EXPECT_FALSE(shownTraversable(test::labelAtWorld(deep, {2.5, y, -0.2})));
  }
}

// The outdoor scene's kerb, 0.15 m high, its top flush with the ground beyond it, seen face on by
// a RoSi tilted 12 deg, for a robot 1.2 m high (it passes under the pipe bridge and reaches the
// kerb). The kerb's top is level with the ground beyond but centimetres from the slab at its
// foot: taken in as that ground, the two levels met there within a step, and the robot's box
// stood over the kerb (3 false cells). Two guards stop it, each alone: no return is taken in
// beside ground lower than it, and a triangle with a taken-in corner spans a step like a join.
TEST(GroundContinuation, AKerbTopDoesNotBringTheLevelAboveWithinAStep) {
  const sim::Scene scene = *sim::builtinScene("outdoor");
  sim::SensorModel sensor;
  sensor.lines = 423;
  sensor.seed = 11;
  sim::ScannerPlacement placement = sim::defaultPlacement(scene);
  placement.axis =
      Eigen::AngleAxisd(12.0 * std::numbers::pi / 180, Eigen::Vector3d::UnitX()) * placement.axis;
  SegmentationParams params;
  params.robot.height = 1.2;
  const test::SimulatedRun run = test::simulateSavedAndSegment(scene, sensor, placement, params);
  ASSERT_TRUE(run.result.trusted()) << run.result.reason;
  const eval::Evaluation e = test::evaluateRun(run, params);
  EXPECT_GT(e.map.traversable_cells, 10000U);
  EXPECT_EQ(e.map.false_traversable_cells, 0U);
}

// A nodding scanner (a 2D scanner tilted about a horizontal axis, as 3DTK's walkway scan was
// taken): its fans cross the floor sideways, each at one distance, and the file gives no turntable
// angle. From `kBendStart` on, the floor bends up across its whole width to `kBendRise` above its
// plane at its far edge (more than the plane's support band): a fan that meets only the bend has
// no ground return of its own to be walked from along it. The ground is followed across the fans,
// as the ground triangles pair them (3DTK's walkway: the floor levelling out beyond a 4.7 deg ramp
// lay 0.05-0.15 m above the ramp's plane, and was red).
constexpr double kBendStart = 3.0, kBendLength = 1.6, kBendRise = 0.09;  // [m]
constexpr double kBendFrom = 0.5;                                        // the bend's side [m]

double bendHeight(double x) {
  if (x <= kBendStart) return 0.0;
  return kBendRise * std::pow(std::sin(std::numbers::pi / 2 * (x - kBendStart) / kBendLength), 2);
}

test::SimulatedRun noddingOverABend() {
  sim::Scene scene;
  scene.name = "bend";
  constexpr double kFarEdge = kBendStart + kBendLength;
  scene.primitives.push_back(
      box("floor", PointClass::kGround, {-3.0, -3.0, -1.0}, {kBendStart, 9.0, 0.0}));
  // Along the scanner's side the floor goes on level, so the floor's plane reaches past the bend.
  scene.primitives.push_back(
      box("side", PointClass::kGround, {kBendStart, -3.0, -1.0}, {6.0, kBendFrom, 0.0}));
  int strip = 0;
  for (double x = kBendStart; x < kFarEdge - 1e-9; x += kColumn)
    scene.primitives.push_back(box("bend_" + std::to_string(strip++), PointClass::kGround,
                                   {x, kBendFrom, -1.0},
                                   {x + kColumn, 9.0, bendHeight(x + kColumn / 2)}));
  sim::SensorModel sensor;
  sensor.lines = 400;
  sensor.max_range = 9.0;
  sim::ScannerPlacement placement;
  placement.position = {0.0, 0.0, 1.0};
  placement.axis = {0.0, 1.0, 0.0};  // the fans hold the sideways axis
  return test::simulateNodding(scene, sensor, placement);
}

TEST(GroundContinuation, AFloorBendingUpAcrossANoddingScannersFansIsGround) {
  const test::SimulatedRun run = noddingOverABend();
  ASSERT_TRUE(run.result.trusted()) << run.result.reason;
  for (const Eigen::Vector2d& p :
       {Eigen::Vector2d(4.0, 2.5), Eigen::Vector2d(3.9, 3.5), Eigen::Vector2d(4.0, 4.0)}) {
    SCOPED_TRACE(p.transpose());
    EXPECT_TRUE(shownTraversable(test::labelAtWorld(run, {p.x(), p.y(), bendHeight(p.x())})));
  }
  EXPECT_EQ(test::evaluateRun(run, SegmentationParams{}).map.false_traversable_cells, 0U);
}

}  // namespace
}  // namespace clearway
