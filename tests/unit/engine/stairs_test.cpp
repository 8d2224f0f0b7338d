// Stairs (issue 11, item 6): staircases are found from their geometry, labelled 5 (or red when
// the robot cannot climb them), their points classed stairs, their rise, tread, direction and
// steps reported; never green, and never found where there are none.

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "clearway/eval/evaluation.h"
#include "clearway/io/result_writer.h"
#include "clearway/io/scan_io.h"
#include "clearway/segmentation/stairs.h"
#include "engine_fixtures.h"
#include "test_support.h"

namespace clearway {
namespace {

double stairsIou(const test::SimulatedRun& run) {
  eval::SegmentationResult result;
  result.point_classes = run.result.point_classes;
  return eval::evaluate(run.simulated.truth, result).classes[std::size_t(PointClass::kStairs)].iou;
}

// The direction of world +x (where the simulated flights climb) as a map-frame yaw [deg].
double worldXYawInMap(const test::SimulatedRun& run) {
  const Eigen::Isometry3d map_from_world =
      run.result.analysis->map_from_scanner *
      run.simulated.truth.placement.worldFromScanner().inverse();
  const Eigen::Vector3d x = map_from_world.linear() * Eigen::Vector3d::UnitX();
  return std::atan2(x.y(), x.x()) * 180 / std::numbers::pi;
}

std::size_t count(const TraversabilityMap& map, CellLabel label) {
  return map.counts[std::size_t(label)];
}

// Every cell a staircase covers is labelled `label`; none of them is green or orange.
void expectStairCells(const PipelineResult& result, CellLabel label) {
  const auto& cells = result.analysis->stairs.cell_staircase;
  ASSERT_EQ(cells.size(), result.map.labels.size());
  std::size_t covered = 0;
  for (std::size_t cell = 0; cell < cells.size(); ++cell) {
    if (cells[cell] < 0) continue;
    ++covered;
    EXPECT_EQ(CellLabel(result.map.labels[cell]), label) << "cell " << cell;
  }
  EXPECT_GT(covered, 50u);
}

// No point of the truth's stairs lies on a green cell.
void expectNoGreenUnderTruthStairs(const test::SimulatedRun& run) {
  const TraversabilityMap& map = run.result.map;
  std::size_t checked = 0;
  for (std::size_t i = 0; i < run.simulated.truth.classes.size(); ++i) {
    if (run.simulated.truth.classes[i] != PointClass::kStairs) continue;
    const Point3f& p = run.simulated.scan.points[i];
    const Eigen::Vector3d m =
        run.result.analysis->map_from_scanner * Eigen::Vector3d(p.x, p.y, p.z);
    const Eigen::Vector2i cell = map.grid.cellOf(m.x(), m.y());
    if (!map.grid.inside(cell.x(), cell.y())) continue;
    ++checked;
    ASSERT_NE(map.label(cell.x(), cell.y()), CellLabel::kTraversable) << "stair point " << i;
  }
  EXPECT_GT(checked, 1000u);
}

TEST(Stairs, HallwayFlightIsFoundWithItsRiseTreadDirectionAndSteps) {
  const auto run = test::simulateAndSegment("hallway", 300);
  ASSERT_TRUE(run.result.trusted());
  const auto& staircases = run.result.analysis->stairs.staircases;
  ASSERT_EQ(staircases.size(), 1u);
  const Staircase& flight = staircases.front();
  EXPECT_EQ(flight.steps(), 4);
  EXPECT_NEAR(flight.rise, 0.17, 0.015);
  EXPECT_NEAR(flight.tread, 0.29, 0.03);
  EXPECT_NEAR(flight.yawDegrees(), worldXYawInMap(run), 5.0);
  EXPECT_NEAR(flight.width(), 1.45, 0.3);
  EXPECT_GE(stairsIou(run), 0.7);
  expectNoGreenUnderTruthStairs(run);
  // A 30 deg flight of 17 cm risers: the default LMF climbs it, with care.
  expectStairCells(run.result, CellLabel::kStairs);
  EXPECT_GT(count(run.result.map, CellLabel::kStairs), 50u);
  // Nothing on the stairs lane is green.
  for (double x = 3.05; x < 3.0 + 4 * 0.29; x += 0.05)
    for (double y = -1.45; y < -0.1; y += 0.05)
      EXPECT_NE(test::labelAtWorld(run, {x, y, 0.0}), CellLabel::kTraversable)
          << "stairs at " << x << ", " << y;
  // The ramp beside it is no staircase.
  EXPECT_EQ(test::labelAtWorld(run, {4.5, 0.8, 0.3}), CellLabel::kTraversable);
}

TEST(Stairs, StairwellFlightOfTwelveStepsIsFound) {
  const auto run = test::simulateAndSegment("stairwell", 300);
  ASSERT_TRUE(run.result.trusted());
  const auto& staircases = run.result.analysis->stairs.staircases;
  ASSERT_EQ(staircases.size(), 1u);
  const Staircase& flight = staircases.front();
  EXPECT_GE(flight.steps(), 10);
  EXPECT_LE(flight.steps(), 12);
  EXPECT_NEAR(flight.rise, 0.17, 0.015);
  EXPECT_NEAR(flight.tread, 0.29, 0.03);
  EXPECT_NEAR(flight.yawDegrees(), worldXYawInMap(run), 5.0);
  EXPECT_GE(stairsIou(run), 0.7);
  expectNoGreenUnderTruthStairs(run);
  expectStairCells(run.result, CellLabel::kStairs);
}

TEST(Stairs, OtherRisersAndTreadsAreMeasuredNotAssumed) {
  // A steep flight: 22 cm risers, 25 cm treads (41 deg).
  sim::SceneParameters steep;
  steep.stair_rise = 0.22;
  steep.stair_tread = 0.25;
  const auto run = test::simulateAndSegment("stairwell", 300, {}, 0.0, 0.0, steep);
  ASSERT_TRUE(run.result.trusted());
  ASSERT_EQ(run.result.analysis->stairs.staircases.size(), 1u);
  const Staircase& flight = run.result.analysis->stairs.staircases.front();
  EXPECT_NEAR(flight.rise, 0.22, 0.015);
  EXPECT_NEAR(flight.tread, 0.25, 0.03);
  EXPECT_GE(stairsIou(run), 0.7);
  expectNoGreenUnderTruthStairs(run);
  // Its risers are higher than the LMF's 20 cm: impassable, and the reason says why.
  expectStairCells(run.result, CellLabel::kImpassable);
  for (std::size_t cell = 0; cell < run.result.map.reasons.size(); ++cell) {
    if (run.result.analysis->stairs.staircaseAt(cell) < 0) continue;
    ASSERT_EQ(CellReason(run.result.map.reasons[cell]), CellReason::kStairsTooSteep);
  }
  EXPECT_EQ(reasonName(CellReason::kStairsTooSteep), "stairs too steep");
  EXPECT_NE(stairVerdict(flight, {}).find("risers of 22 cm"), std::string::npos);
}

TEST(Stairs, TheRobotsStairAbilityDecidesCarefulOrImpassable) {
  const auto run = test::simulateAndSegment("hallway", 300);
  ASSERT_EQ(run.result.analysis->stairs.staircases.size(), 1u);
  SegmentationParams params;
  expectStairCells(run.result, CellLabel::kStairs);
  params.robot.max_stair_slope_deg = 25.0;  // the flight is 30 deg
  const PipelineResult shallow = rerunForRobot(run.simulated.scan, run.result.analysis, params);
  expectStairCells(shallow, CellLabel::kImpassable);
  EXPECT_EQ(count(shallow.map, CellLabel::kStairs), 0u);
  params = {};
  params.robot.max_stair_rise = 0.15;  // the risers are 17 cm
  expectStairCells(rerunForRobot(run.simulated.scan, run.result.analysis, params),
                   CellLabel::kImpassable);
  params = {};
  params.robot.width = 1.6;  // wider than the 1.45 m flight
  params.robot.length = 1.8;
  const PipelineResult wide = rerunForRobot(run.simulated.scan, run.result.analysis, params);
  expectStairCells(wide, CellLabel::kImpassable);
  const std::size_t stair_cell =
      std::size_t(std::find_if(wide.analysis->stairs.cell_staircase.begin(),
                               wide.analysis->stairs.cell_staircase.end(),
                               [](std::int16_t s) { return s >= 0; }) -
                  wide.analysis->stairs.cell_staircase.begin());
  EXPECT_EQ(CellReason(wide.map.reasons[stair_cell]), CellReason::kTooNarrow);
}

// The 3D view draws a flight as the map does: stairs the robot can climb (not red obstacle cubes,
// though its treads stand higher than its step), red where it cannot.
TEST(Stairs, TheSceneDrawsTheFlightAsTheMapDoes) {
  const auto run = test::simulateAndSegment("hallway", 300);
  ASSERT_EQ(run.result.analysis->stairs.staircases.size(), 1u);
  const Staircase& flight = run.result.analysis->stairs.staircases.front();
  const Eigen::Isometry3d map_from_scanner = run.result.analysis->map_from_scanner;
  auto cubesOnTheFlight = [&](const PipelineResult& result, CellLabel label) {
    std::size_t cubes = 0;
    for (const SceneBox& cube : result.scene.obstacles) {
      const Eigen::Vector3d centre = map_from_scanner * cube.center.cast<double>();
      const Eigen::Vector2d along(centre.head<2>());
      const double up = flight.up.dot(along), across = flight.across.dot(along);
      const bool over_flight = up > flight.start() + 0.05 && up < flight.end() - 0.05 &&
                               across > flight.across_min + 0.05 &&
                               across < flight.across_max - 0.05;
      cubes += over_flight && cube.label == label;
    }
    return cubes;
  };
  EXPECT_GT(cubesOnTheFlight(run.result, CellLabel::kStairs), 20u);
  EXPECT_EQ(cubesOnTheFlight(run.result, CellLabel::kImpassable), 0u);
  SegmentationParams params;
  params.robot.max_stair_rise = 0.15;  // the risers are 17 cm: not for this robot
  const PipelineResult cannot = rerunForRobot(run.simulated.scan, run.result.analysis, params);
  EXPECT_EQ(cubesOnTheFlight(cannot, CellLabel::kStairs), 0u);
  EXPECT_GT(cubesOnTheFlight(cannot, CellLabel::kImpassable), 20u);
}

TEST(Stairs, ReportListsEachStaircase) {
  const auto run = test::simulateAndSegment("hallway", 300);
  const SegmentationParams params;
  const auto report = nlohmann::json::parse(reportJson(run.result, params, "hallway.pcd"));
  ASSERT_TRUE(report.contains("stairs"));
  ASSERT_EQ(report["stairs"].size(), 1u);
  const auto& flight = report["stairs"][0];
  EXPECT_EQ(flight["steps"].get<int>(), 4);
  EXPECT_NEAR(flight["rise"].get<double>(), 0.17, 0.015);
  EXPECT_NEAR(flight["tread"].get<double>(), 0.29, 0.03);
  EXPECT_NEAR(flight["direction_deg"].get<double>(), worldXYawInMap(run), 5.0);
  EXPECT_NEAR(flight["slope_deg"].get<double>(), 30.4, 3.0);
  EXPECT_TRUE(flight["climbable"].get<bool>());
  EXPECT_FALSE(flight.contains("reason"));
  EXPECT_EQ(report["cells"]["stairs"].get<std::size_t>(),
            count(run.result.map, CellLabel::kStairs));
  // The console's hover readout names the flight under the cursor through the per-cell index.
  const auto& stairs = run.result.analysis->stairs;
  const auto cell = std::find_if(stairs.cell_staircase.begin(), stairs.cell_staircase.end(),
                                 [](std::int16_t s) { return s >= 0; });
  ASSERT_NE(cell, stairs.cell_staircase.end());
  const std::string text = describeStaircase(stairs.staircases[std::size_t(*cell)], params.robot);
  EXPECT_NE(text.find("4 steps, rise 17 cm, tread 29 cm"), std::string::npos) << text;
  EXPECT_NE(text.find("climbable with care"), std::string::npos) << text;
}

TEST(Stairs, NoStairsWhereThereAreNone) {
  for (const std::string scene : {"garage", "doorways", "outdoor", "glass"}) {
    const auto run = test::simulateAndSegment(scene, 300);
    ASSERT_TRUE(run.result.trusted()) << scene;
    EXPECT_TRUE(run.result.analysis->stairs.staircases.empty()) << scene;
    EXPECT_EQ(count(run.result.map, CellLabel::kStairs), 0u) << scene;
    EXPECT_EQ(std::count(run.result.point_classes.begin(), run.result.point_classes.end(),
                         PointClass::kStairs),
              0)
        << scene;
  }
}

TEST(Stairs, ASteepRampIsNoStaircase) {
  // A 30 deg ramp rises 5.8 cm over every 10 cm cell: riser-like cells everywhere, but never a
  // flat tread between them.
  sim::SceneParameters steep;
  steep.ramp_slope_deg = 30.0;
  const auto run = test::simulateAndSegment("hallway", 300, {}, 0.0, 0.0, steep);
  ASSERT_TRUE(run.result.trusted());
  ASSERT_EQ(run.result.analysis->stairs.staircases.size(), 1u);  // the stairs lane, not the ramp
  for (double x = 3.2; x < 4.0; x += 0.1)
    EXPECT_NE(test::labelAtWorld(run, {x, 0.8, 0.0}), CellLabel::kStairs) << "ramp at " << x;
}

TEST(Stairs, TheStairAbilityIsARobotParameterOnTheCommandLine) {
  test::TemporaryDirectory directory;
  const auto scan = (directory / "h.pcd").string();
  ASSERT_EQ(test::runCli("simulate hallway --lines 200 -o " + test::shellQuote(scan)).exit_code, 0);
  const auto out = (directory / "out").string();
  const auto result = test::runCli("segment " + test::shellQuote(scan) + " -o " +
                                   test::shellQuote(out) + " --max-stair-rise 0.15");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const auto report = nlohmann::json::parse(test::readBytes(directory / "out" / "report.json"));
  ASSERT_EQ(report.at("stairs").size(), 1u);
  EXPECT_FALSE(report["stairs"][0].at("climbable").get<bool>());
  EXPECT_NE(report["stairs"][0].at("reason").get<std::string>().find("risers of 17 cm"),
            std::string::npos);
  EXPECT_EQ(report.at("cells").at("stairs").get<int>(), 0);
  EXPECT_DOUBLE_EQ(report.at("params").at("robot").at("max_stair_rise").get<double>(), 0.15);
  EXPECT_NE(test::runCli("segment " + test::shellQuote(scan) + " -o " + test::shellQuote(out) +
                         " --max-stair-slope 95")
                .exit_code,
            0);
}

TEST(Stairs, DetectorRangesAreValidated) {
  SegmentationParams params;
  params.stairs.min_rise = 0.3;  // above max_rise
  const auto reasons = params.validate();
  ASSERT_FALSE(reasons.empty());
  EXPECT_NE(reasons.front().find("stairs.min_rise"), std::string::npos);
  EXPECT_DOUBLE_EQ(paramsFromJson(nlohmann::json{{"robot", {{"max_stair_slope_deg", 30.0}}}})
                       .robot.max_stair_slope_deg,
                   30.0);
}

TEST(RealScans, OctomapStaircaseIsMeasuredAndNeverGreen) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, "octomap-stairs/scan.dat");
  const PipelineResult result = runPipeline(loadScan(file), {});
  ASSERT_TRUE(result.trusted()) << result.reason;
  const auto& staircases = result.analysis->stairs.staircases;
  ASSERT_FALSE(staircases.empty());
  // The flight: the staircase with the most steps. SOURCE.txt: risers ~0.14 m, treads ~0.32 m,
  // climbing along the file's +x.
  const Staircase& flight = *std::max_element(
      staircases.begin(), staircases.end(),
      [](const Staircase& a, const Staircase& b) { return a.steps() < b.steps(); });
  EXPECT_GE(flight.steps(), 5);
  EXPECT_NEAR(flight.rise, 0.14, 0.02);
  EXPECT_NEAR(flight.tread, 0.32, 0.04);
  const Eigen::Vector3d x = result.analysis->map_from_scanner.linear() * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(flight.yawDegrees(), std::atan2(x.y(), x.x()) * 180 / std::numbers::pi, 10.0);
  expectStairCells(result, CellLabel::kStairs);
  EXPECT_GT(
      std::count(result.point_classes.begin(), result.point_classes.end(), PointClass::kStairs),
      1000);
  // Never green on the flight (SOURCE.txt: x ~ 5.1 .. 9.5 m, y ~ -3 .. 3 m).
  for (double px = 5.2; px <= 9.0; px += 0.1)
    for (double py = -2.5; py <= 2.5; py += 0.1) {
      const Eigen::Vector3d m = result.analysis->map_from_scanner * Eigen::Vector3d(px, py, 0.0);
      const Eigen::Vector2i cell = result.map.grid.cellOf(m.x(), m.y());
      if (!result.map.grid.inside(cell.x(), cell.y())) continue;
      EXPECT_NE(result.map.label(cell.x(), cell.y()), CellLabel::kTraversable)
          << "stairs at " << px << ", " << py;
    }
}

}  // namespace
}  // namespace clearway
