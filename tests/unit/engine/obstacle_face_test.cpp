// Obstacles seen only in part, whose edge lies beyond their samples: a box just taller than the
// robot's step, seen from above, its top sampled centimetres behind its edge (a surface seen at a
// grazing angle) and its face's lower returns, under the step, where it begins: the robot's box
// must stop at the face, not at the first return on the top (docs/ALGORITHM.md, "The face of an
// obstacle seen from above"); a box whose top lies between two lines one above the other; a
// shelf whose end lies beyond its last samples (docs/ALGORITHM.md, "Sparse scans never lie").

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <numbers>

#include "clearway/eval/evaluation.h"
#include "clearway/pipeline.h"
#include "engine_fixtures.h"

namespace clearway {
namespace {

const auto box = test::solidBox;

// A walled floor 10 x 8 m with one low box (0.4 x 0.4 m, `height` tall) at (x, y), scanned from
// 1.2 m above the floor with the turntable axis tilted down ahead, as on the robot's arm.
sim::Scene lowBoxScene(double height, double x, double y) {
  sim::Scene scene;
  scene.name = "low-box";
  scene.primitives = {
      box("floor", PointClass::kGround, {2, 0, -0.05}, {10, 8, 0.1}),
      box("back", PointClass::kWall, {-3.1, 0, 1.25}, {0.2, 8, 2.5}),
      box("front", PointClass::kWall, {7.1, 0, 1.25}, {0.2, 8, 2.5}),
      box("left", PointClass::kWall, {2, 4.1, 1.25}, {10, 0.2, 2.5}),
      box("right", PointClass::kWall, {2, -4.1, 1.25}, {10, 0.2, 2.5}),
      box("low_box", PointClass::kObstacle, {x, y, height / 2}, {0.4, 0.4, height}),
  };
  return scene;
}

// The simulated run of `scene`, scored by the simulator's truth; the turntable axis tilted by
// `tilt_deg` about x, as `clearway-cli simulate --tilt` does.
eval::Evaluation evaluateRun(const sim::Scene& scene, int lines, std::uint32_t seed,
                             double robot_width, double tilt_deg = 0.0) {
  sim::SensorModel sensor;
  sensor.lines = lines;
  sensor.seed = seed;
  sim::ScannerPlacement placement;
  placement.position = {0.0, 0.0, 1.2};
  placement.axis =
      Eigen::AngleAxisd(tilt_deg * std::numbers::pi / 180.0, Eigen::Vector3d::UnitX()) *
      Eigen::Vector3d(1.0, 0.0, -0.3).normalized();
  const sim::SimulatedScan simulated = sim::simulateRosi(scene, sensor, placement);
  SegmentationParams params;
  params.robot.width = robot_width;
  const PipelineResult run = runPipeline(simulated.scan, params);
  EXPECT_TRUE(run.trusted()) << run.reason;
  eval::SegmentationResult result;
  result.robot = {params.robot.width, params.robot.length, params.robot.height,
                  params.robot.max_step};
  result.map = eval::resultMapOf(run.map.grid, run.map.labels, run.analysis->map_from_scanner);
  result.has_map = true;
  const eval::Evaluation e = eval::evaluate(simulated.truth, result);
  EXPECT_GT(e.map.traversable_cells, 1000u);
  return e;
}

// No false-traversable cell in front of the face of the 0.4 m box centred at y (the robot's box
// reaching into it from the scanner's side). Its corners are left: there the top's first samples
// lie a few centimetres in from both edges (docs/ALGORITHM.md, known limits).
void expectNoneInFrontOfTheFace(const eval::Evaluation& e, double y) {
  ASSERT_LT(e.map.false_traversable_cells, 20u) << "more than the listed cells";
  for (const Eigen::Vector3d& cell : e.map.false_cells)
    EXPECT_GT(std::abs(cell.y() - y), 0.2)
        << "false-traversable cell in front of the face at x " << cell.x() << ", y " << cell.y();
}

TEST(ObstacleFace, TheRobotStopsAtTheFaceOfABoxJustOverItsStep) {
  // Without the face, 24 cells in front of the box were careful with the robot 5-8 cm into it.
  expectNoneInFrontOfTheFace(evaluateRun(lowBoxScene(0.11, 4.5, 2.0), 300, 3, 0.85), 2.0);
}

TEST(ObstacleFace, AtOtherWidthsAndDensitiesToo) {
  for (const double width : {0.6, 1.0}) {
    SCOPED_TRACE(width);
    expectNoneInFrontOfTheFace(evaluateRun(lowBoxScene(0.11, 3.0, -1.5), 150, 4, width), -1.5);
  }
  expectNoneInFrontOfTheFace(evaluateRun(lowBoxScene(0.2, 3.0, -1.5), 90, 3, 0.85), -1.5);
}

// A box 0.13 m tall beside the scanner (yawed 51 deg, 3.8 m away to the left ahead), scanned at 100
// lines with the forward turntable tilted 15 deg: there the lines lie one above the other, and one
// line met only the box's side face at a grazing angle, 4-8 cm up, under the step; its top lies
// between that line and the next, whose beam passed 15 cm over it. Counted sideways, the lines
// were 0.19 m apart there and the floor around was vouched for: 64 cells green or careful with
// the robot over the box (docs/ALGORITHM.md, "Sparse scans never lie").
TEST(ObstacleFace, ABoxWhoseTopLiesBetweenLinesOneAboveTheOtherIsNotDrivenOver) {
  sim::Scene scene;
  scene.name = "box-beside";
  scene.primitives = {box("floor", PointClass::kGround, {4, 0, -0.05}, {14, 10, 0.1}),
                      box("box", PointClass::kObstacle, {2.78, 2.57, 0.064}, {0.17, 0.36, 0.128})};
  scene.primitives.back().yaw_deg = 50.9;
  const eval::Evaluation e = evaluateRun(scene, 100, 1, RobotParams{}.width, 15.0);
  EXPECT_EQ(e.map.false_traversable_cells, 0u);
  EXPECT_GT(e.map.traversable_cells, 3000u);  // the floor ahead stays green
}

// A shelf 0.6 m up along a side wall (a 4 cm board, 3 m long, 0.6 m deep), scanned at 100 lines
// with the forward turntable tilted 15 deg. Its top is seen from above at a grazing angle, its
// samples 0.35 m apart along a line, and the last ones lie 0.17-0.25 m short of its far end; the
// floor beyond and under it is seen by beams that pass under the board. Behind the last samples,
// between their beams' continuations, the board may run on over floor that was seen: the shadow
// walk of overhangs (hiddenCells) now follows every cell whose lowest blocking point stands two
// steps off the ground, not only those too low for the robot (above half its height). Before, 26
// cells were green or careful with the robot's box up to 0.12 m under the board's end.
TEST(ObstacleFace, AShelfsUnseenEndIsNotStoodUnder) {
  sim::Scene scene;
  scene.name = "side-shelf";
  scene.primitives = {box("floor", PointClass::kGround, {4, 0, -0.05}, {14, 10, 0.1}),
                      box("wall", PointClass::kWall, {4, 1.6, 1.25}, {14, 0.2, 2.5}),
                      box("shelf", PointClass::kObstacle, {4, 1.2, 0.58}, {3, 0.6, 0.04})};
  const eval::Evaluation e = evaluateRun(scene, 100, 1, RobotParams{}.width, 15.0);
  EXPECT_EQ(e.map.false_traversable_cells, 0u);
  EXPECT_GT(e.map.traversable_cells, 3000u);  // the floor ahead stays green
}

}  // namespace
}  // namespace clearway
