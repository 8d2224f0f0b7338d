// Two ground planes that meet at a low kerb seen from above: the kerb's face turns away from the
// scanner, so between the last return on the upper floor and the first on the lower one nothing
// was measured. The ground triangles join the two floors there when the kerb is no higher than
// the robot's step, and the map keeps that step, so a robot with a smaller step is still stopped
// (docs/ALGORITHM.md, "Ground planes that meet at a kerb").

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <optional>

#include "clearway/eval/evaluation.h"
#include "clearway/pipeline.h"
#include "engine_fixtures.h"

namespace clearway {
namespace {

constexpr double kKerbX = 2.0;  // where the upper floor ends [m]

// A RoSi 1 m above an upper floor that drops by `drop` at x = kKerbX to a lower floor.
test::SimulatedRun kerbScene(double drop, const SegmentationParams& params = {}) {
  sim::Scene scene;
  scene.name = "kerb";
  sim::Primitive upper;
  upper.name = "upper_floor";
  upper.point_class = PointClass::kGround;
  upper.center = {kKerbX - 4.0, 0.0, -0.5};
  upper.size = {8.0, 12.0, 1.0};
  scene.primitives.push_back(upper);
  sim::Primitive lower = upper;
  lower.name = "lower_floor";
  lower.center = {kKerbX + 4.0, 0.0, -0.5 - drop};
  scene.primitives.push_back(lower);
  return test::simulateFromOrigin(scene, params);
}

bool shownTraversable(CellLabel label) {
  return label == CellLabel::kTraversable || label == CellLabel::kCareful;
}

TEST(GroundSeam, AKerbLowerThanTheStepIsCrossed) {
  const double drop = 0.07;  // under the default robot's 0.1 m step, over 0.05 m
  const test::SimulatedRun run = kerbScene(drop);
  ASSERT_TRUE(run.result.trusted()) << run.result.reason;
  // The strip along the kerb that no beam reached is ground: without the join it was unobserved
  // and the robot's box could stand nowhere near it ("too narrow" on both sides).
  for (const double y : {-1.0, 0.0, 1.0}) {
    SCOPED_TRACE(y);
    EXPECT_TRUE(shownTraversable(test::labelAtWorld(run, {kKerbX + 0.03, y, -drop / 2})));
    EXPECT_TRUE(shownTraversable(test::labelAtWorld(run, {kKerbX - 0.3, y, 0.0})));
    EXPECT_TRUE(shownTraversable(test::labelAtWorld(run, {kKerbX + 0.3, y, -drop})));
  }
  EXPECT_TRUE(test::connectedInMap(run, {1.0, 0.0, 0.0}, {4.0, 0.0, -drop}));
}

TEST(GroundSeam, AKerbHigherThanTheStepIsNotCrossed) {
  const double drop = 0.15;
  const test::SimulatedRun run = kerbScene(drop);
  ASSERT_TRUE(run.result.trusted()) << run.result.reason;
  EXPECT_FALSE(test::connectedInMap(run, {1.0, 0.0, 0.0}, {4.0, 0.0, -drop}));
  EXPECT_FALSE(shownTraversable(test::labelAtWorld(run, {kKerbX + 0.03, 0.0, -drop / 2})));
}

TEST(GroundSeam, ARobotWithASmallerStepIsStoppedWhereTheJoinWasMade) {
  const double drop = 0.07;
  test::SimulatedRun run = kerbScene(drop);
  ASSERT_TRUE(test::connectedInMap(run, {1.0, 0.0, 0.0}, {4.0, 0.0, -drop}));
  // The console's robot re-run keeps the analysis, joins and all: the map must still say no.
  SegmentationParams smaller_step;
  smaller_step.robot.max_step = 0.05;
  run.result = rerunForRobot(run.simulated.scan, run.result.analysis, smaller_step);
  ASSERT_TRUE(run.result.trusted()) << run.result.reason;
  EXPECT_FALSE(test::connectedInMap(run, {1.0, 0.0, 0.0}, {4.0, 0.0, -drop}));
  bool blocked_across = false;
  for (double x = kKerbX - 0.1; x < kKerbX + 0.2; x += 0.01)
    blocked_across |= test::labelAtWorld(run, {x, 0.0, -drop / 2}) == CellLabel::kImpassable;
  EXPECT_TRUE(blocked_across) << "no impassable cell across the kerb for a 0.05 m step";
}

TEST(GroundSeam, AKerbSeenFaceOnIsNotSplitByTheUpperLevelsBand) {
  // The outdoor scene's 0.15 m kerb from 3.3 m before it (beyond the pipe bridge), its face
  // turned to the scanner. The upper level's support band takes in the top 5 cm of the face, so
  // the cells at its edge stood about 0.1 m up: measured cell to cell the 0.15 m step split in
  // two that a 0.1 m robot takes, the upper level was reached, and the robot's box stood over the
  // kerb's edge (332 false cells).
  const sim::Scene scene = *sim::builtinScene("outdoor");
  sim::SensorModel sensor;
  sensor.lines = 150;
  sensor.seed = 13;
  sim::ScannerPlacement placement = sim::defaultPlacement(scene);
  placement.position = {6.5, 0.0, 1.2};
  const test::SimulatedRun run = test::simulateSavedAndSegment(scene, sensor, placement);
  ASSERT_TRUE(run.result.trusted()) << run.result.reason;
  const eval::Evaluation e = test::evaluateRun(run);
  // (Green and careful cells only: the floor to the sides, where the forward turntable's lines lie
  // one above the other too far apart to vouch for it, is orange, "too sparse".)
  EXPECT_GT(e.map.traversable_cells, 2000U);
  EXPECT_EQ(e.map.false_traversable_cells, 0U);
  EXPECT_FALSE(test::connectedInMap(run, {8.5, 0.0, 0.0}, {12.0, 0.0, 0.15}));
}

// The outdoor scene's paving slabs meet at x = 4 m with a step that grows along the joint (the
// third slab is rolled 2 deg): about 0.05 m down near y = -2 m, 0.05 m up near y = 1 m, 0.13 m up
// near y = 3.5 m. A view of it and a robot, as a randomised sweep drew them (scripts/variant-sweep
// draws the same way). The green and careful cells counted leave out the floor to the sides, where
// the forward turntable's lines lie one above the other too far apart to vouch for it (orange).
struct SlabJointView {
  int lines;
  std::uint32_t seed;
  double noise;  // range noise sigma [m]
  bool mixed_pixels;
  double tilt_deg, roll_deg;  // the turntable axis tilted about world x, then rolled
  double robot_width, robot_length, robot_step;
};

// The simulated view of the joint, segmented and scored for its robot; the scanner at the scene's
// place unless `position` is given.
eval::Evaluation slabJoint(const SlabJointView& view,
                           const std::optional<Eigen::Vector3d>& position = std::nullopt) {
  const sim::Scene scene = *sim::builtinScene("outdoor");
  sim::SensorModel sensor;
  sensor.lines = view.lines;
  sensor.seed = view.seed;
  sensor.range_noise_sigma = view.noise;
  sensor.mixed_pixels = view.mixed_pixels;
  sim::ScannerPlacement placement = sim::defaultPlacement(scene);
  placement.axis =
      Eigen::AngleAxisd(view.tilt_deg * std::numbers::pi / 180, Eigen::Vector3d::UnitX()) *
      placement.axis;
  placement.axis_roll_deg = view.roll_deg;
  if (position) placement.position = *position;
  SegmentationParams params;
  params.robot.width = view.robot_width;
  params.robot.length = view.robot_length;
  params.robot.max_step = view.robot_step;
  const test::SimulatedRun run = test::simulateSavedAndSegment(scene, sensor, placement, params);
  EXPECT_TRUE(run.result.trusted()) << run.result.reason;
  return test::evaluateRun(run, params);
}

TEST(GroundSeam, AStepBetweenTwoScanLinesKeepsTheBoxOffItsEdge) {
  // The 0.13 m step up seen at 120 lines: one line met only the step's face (5 cm up) and the
  // next the upper slab 0.13 m farther on; between them nothing. The lower side's last cell held
  // the face's returns and looked like floor: the robot's box, 0.6 m wide, stood 7 cm onto the
  // upper slab (4 false cells; scripts/variant-sweep).
  const eval::Evaluation e = slabJoint({120, 3, 0.005, true, 35.0, 20.0, 0.6, 1.2, 0.1});
  EXPECT_GT(e.map.traversable_cells, 4000U);
  EXPECT_EQ(e.map.false_traversable_cells, 0U);
}

TEST(GroundSeam, AStepTheTrianglesSpreadIsStillAStepForTheRobot) {
  // Near y = 0.85 m, where slab_2 stands 0.04-0.07 m above slab_1 under the robot's box, with
  // 1.5 cm range noise, for a robot whose step is 0.05 m. The ground triangles spread the step
  // over two or three cells, none of which differed from the next by the step: the box stood
  // across it (3 false cells).
  const eval::Evaluation e = slabJoint({350, 409, 0.015, false, 14.91, 11.27, 0.739, 1.35, 0.05});
  EXPECT_GT(e.map.traversable_cells, 5000U);
  EXPECT_EQ(e.map.false_traversable_cells, 0U);
}

TEST(GroundSeam, ASlabJointJustHigherThanTheStepIsNotCrossed) {
  // Seen from 1 m to the left, where the joint rises 0.14-0.17 m (y = 3.7-4.6 m) for a robot
  // whose step is 0.14 m: the plane fitted over the rolled slab, and slab_3 beyond it, passes 2 cm
  // below the slab at the joint, and the cells either side hold the face's returns, so the joint
  // measured 0.12-0.13 m and the robot's box stood across it (140 false cells). Measured as a
  // join's step is, with 2 cm for what either side is measured to, it is not crossed.
  const eval::Evaluation e =
      slabJoint({154, 2, 0.0034, false, 21.34, 0.0, 0.928, 0.926, 0.14}, {{0.81, 0.919, 1.2}});
  // (Without the floor beside the scanner, where the band up to the robot's height was above its
  // view: docs/ALGORITHM.md, "Above the scanner's view"; nor the floor to the sides, too sparse.)
  EXPECT_GT(e.map.traversable_cells, 5000U);
  EXPECT_EQ(e.map.false_traversable_cells, 0U);
}

TEST(GroundSeam, ADropInItsOwnShadowIsAStepForTheRobot) {
  // Near y = -2 m, where slab_2 falls 0.05-0.07 m below slab_1, away from the scanner: the ground
  // behind the edge lies in its shadow, and the triangles bridged it from the edge to the first
  // return beyond, 0.3-0.7 m, a gentle slope on the map. For a robot whose step is 0.05 m the box
  // stood across the drop (81 false cells).
  const eval::Evaluation e = slabJoint({423, 821, 0.0, false, -13.82, 7.63, 0.826, 1.035, 0.05});
  EXPECT_GT(e.map.traversable_cells, 6000U);
  EXPECT_EQ(e.map.false_traversable_cells, 0U);
}

// A ramp 2 m wide running down 5 deg from an upper floor, its open sides dropping to a lower floor
// beside it: 0.26 m where it starts, nothing where it ends. Seen at 200 lines with 2 cm range
// noise and mixed pixels, the side's edge was a line of unobserved cells between the ramp's cells
// and the lower floor's; the cells either side measured within the robot's step of each other
// where the drop was 0.10-0.14 m, and the robot's box stood over the unobserved line, as it may
// over a beam that fell between two cells (75 false cells; the probe of docs/ALGORITHM.md, "Known
// limits"). Across one unobserved cell, two ground planes are now held as far apart as where their
// cells meet side by side.
TEST(GroundSeam, ARampsSideDropAcrossAnUnseenCellIsNotStraddled) {
  sim::Scene scene;
  scene.name = "ramp-with-open-sides";
  auto slab = [](const char* name, const Eigen::Vector3d& center, const Eigen::Vector3d& size) {
    return test::solidBox(name, PointClass::kGround, center, size);
  };
  constexpr double kSlope = 5.0 * std::numbers::pi / 180.0;
  constexpr double kRampLength = 3.0;                  // along x, from x = 2.5 m
  const double fall = kRampLength * std::tan(kSlope);  // 0.26 m
  scene.primitives = {slab("upper", {-0.25, 0.0, -0.4}, {5.5, 10.0, 0.8}),
                      slab("lower", {7.25, 0.0, -fall - 0.05}, {9.5, 10.0, 0.1})};
  sim::Primitive ramp =
      slab("ramp", Eigen::Vector3d::Zero(), {kRampLength / std::cos(kSlope), 2.0, 1.5});
  ramp.pitch_deg = 5.0;
  // Its top face runs from the upper floor's edge (2.5, 0) down to the lower floor.
  const Eigen::Vector3d top_middle(2.5 + kRampLength / 2, 0.0, -fall / 2);
  ramp.center = top_middle - ramp.rotation() * Eigen::Vector3d(0.0, 0.0, 0.75);
  scene.primitives.push_back(ramp);

  sim::SensorModel sensor;
  sensor.lines = 200;
  sensor.seed = 3;
  sensor.range_noise_sigma = 0.02;
  sensor.mixed_pixels = true;
  const test::SimulatedRun run = test::simulateFromTheArm(scene, sensor);
  ASSERT_TRUE(run.result.trusted()) << run.result.reason;
  const eval::Evaluation e = test::evaluateRun(run);
  EXPECT_EQ(e.map.false_traversable_cells, 0U);
  EXPECT_GT(e.map.traversable_cells, 15000U);
  // Down the ramp, and around it on the lower floor.
  EXPECT_TRUE(test::connectedInMap(run, {1.0, 0.0, 0.0}, {7.0, 0.0, -fall}));
}

// A pit 1 x 1 m and 0.7 m deep, 2 m ahead, seen at 200 lines from 1.2 m up: between the last
// return on the floor before its rim and the first one inside it, a cell or two were not seen. The
// robot's box may reach to the middle of an unobserved cell (a door's jamb casts one, and a door
// 5 cm wider than the robot is passed), but beside a drop the rim may lie anywhere in it: the box
// stood 1-2 cm over the rim (2 false cells; the probe of docs/ALGORITHM.md, "Known limits").
// Unobserved cells beside ground too steep or of another level now block as a whole.
TEST(GroundSeam, APitsRimIsNotReachedOverWhereItsEdgeWasNotSeen) {
  sim::Scene scene;
  scene.name = "pit";
  const auto solid = test::solidBox;
  constexpr double kDepth = 0.7;
  scene.primitives = {
      solid("floor_near", PointClass::kGround, {-0.5, 0.0, -0.05}, {5.0, 10.0, 0.1}),
      solid("floor_far", PointClass::kGround, {7.0, 0.0, -0.05}, {8.0, 10.0, 0.1}),
      solid("floor_right", PointClass::kGround, {2.5, -2.75, -0.05}, {1.0, 4.5, 0.1}),
      solid("floor_left", PointClass::kGround, {2.5, 2.75, -0.05}, {1.0, 4.5, 0.1}),
      solid("pit_bottom", PointClass::kGround, {2.5, 0.0, -kDepth - 0.05}, {1.4, 1.4, 0.1}),
      solid("pit_side_near", PointClass::kWall, {1.9, 0.0, -0.4}, {0.2, 1.4, kDepth - 0.1}),
      solid("pit_side_far", PointClass::kWall, {3.1, 0.0, -0.4}, {0.2, 1.4, kDepth - 0.1}),
      solid("pit_side_right", PointClass::kWall, {2.5, -0.6, -0.4}, {1.4, 0.2, kDepth - 0.1}),
      solid("pit_side_left", PointClass::kWall, {2.5, 0.6, -0.4}, {1.4, 0.2, kDepth - 0.1})};
  sim::SensorModel sensor;
  sensor.lines = 200;
  const test::SimulatedRun run = test::simulateFromTheArm(scene, sensor);
  ASSERT_TRUE(run.result.trusted()) << run.result.reason;
  const eval::Evaluation e = test::evaluateRun(run);
  EXPECT_EQ(e.map.false_traversable_cells, 0U);
  EXPECT_GT(e.map.traversable_cells, 15000U);
  // Around the pit to the floor beyond it.
  EXPECT_TRUE(test::connectedInMap(run, {0.8, 0.0, 0.0}, {4.5, 0.0, 0.0}));
}

// A ledge's rim seen from the floor above it: the rays go on past the rim and meet the lower
// floor only well beyond the face under it, so between the last return on the upper floor and the
// ray that missed it lie unobserved cells with free ground towards the scanner and a drop beyond.
// The rim may lie anywhere in them; taken by their centre, the small robot's box stood up to
// 2.5 cm more over the rim (10 false cells; the probe of docs/ALGORITHM.md, "Known limits").
// Unobserved cells where the ground ends along the rays now block as a whole.
TEST(GroundSeam, ALedgesRimIsNotReachedOverWhereTheRaysWentOnPastIt) {
  sim::Scene scene;
  scene.name = "ledge";
  const auto solid = test::solidBox;
  constexpr double kDrop = 0.3, kRim = 4.0;
  scene.primitives = {
      solid("upper", PointClass::kGround, {(kRim - 3) / 2, 0.0, -0.05}, {kRim + 3, 10.0, 0.1}),
      solid("lower", PointClass::kGround, {(kRim + 11) / 2, 0.0, -kDrop - 0.05},
            {11 - kRim, 10.0, 0.1}),
      solid("ledge_face", PointClass::kWall, {kRim - 0.1, 0.0, -kDrop / 2 - 0.05},
            {0.2, 10.0, kDrop - 0.1})};
  sim::SensorModel sensor;
  sensor.lines = 200;
  SegmentationParams params;
  params.robot.width = 0.5;
  params.robot.length = 0.6;
  params.robot.height = 0.45;
  params.robot.max_step = 0.05;
  const test::SimulatedRun run = test::simulateFromTheArm(scene, sensor, params);
  ASSERT_TRUE(run.result.trusted()) << run.result.reason;
  const eval::Evaluation e = test::evaluateRun(run, params);
  EXPECT_EQ(e.map.false_traversable_cells, 0U);
  EXPECT_GT(e.map.traversable_cells, 3000U);
  // Up to the rim and along it.
  EXPECT_TRUE(test::connectedInMap(run, {1.0, 0.0, 0.0}, {3.5, 1.5, 0.0}));
}

}  // namespace
}  // namespace clearway
