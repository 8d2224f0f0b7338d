// The robot's band above the ground must have been in the scanner's view before a cell is green
// (docs/ALGORITHM.md, "Above the scanner's view"). A RoSi whose turntable axis points down sees
// only below itself: an overhang between its height and the robot's is never measured, and the
// outdoor scene's pipe bridge was crossed by 873 green or careful cells.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <numbers>
#include <string>

#include "../../../core/src/segmentation/view_limit.h"
#include "clearway/eval/evaluation.h"
#include "clearway/pipeline.h"
#include "clearway/sim/builtin_scenes.h"
#include "clearway/traversability/reachability.h"
#include "engine_fixtures.h"

namespace clearway {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

test::SimulatedRun outdoorSeenWithTheAxisDown(const SegmentationParams& params) {
  const sim::Scene scene = *sim::builtinScene("outdoor");
  sim::SensorModel sensor;
  sensor.lines = 200;
  sim::ScannerPlacement placement = sim::defaultPlacement(scene);
  placement.axis = -Eigen::Vector3d::UnitZ();
  return test::simulateSavedAndSegment(scene, sensor, placement, params);
}

std::size_t cellsWithReason(const TraversabilityMap& map, CellReason reason) {
  return std::size_t(std::count(map.reasons.begin(), map.reasons.end(), std::uint8_t(reason)));
}

TEST(AboveTheView, AnAxisPointingDownShowsNothingGreenUnderAPipeItCannotSee) {
  const SegmentationParams params;  // the robot is 1.5 m tall, the scanner 1.2 m up
  const test::SimulatedRun run = outdoorSeenWithTheAxisDown(params);
  ASSERT_TRUE(run.result.analysis->ground_found) << run.result.reason;
  const TraversabilityMap& map = run.result.map;
  const eval::Evaluation e = test::evaluateRun(run, params);
  EXPECT_EQ(e.map.false_traversable_cells, 0U);
  EXPECT_EQ(map.counts[std::size_t(CellLabel::kTraversable)], 0U);
  // The floor it saw is still shown, orange, with the reason.
  EXPECT_GT(cellsWithReason(map, CellReason::kAboveView), 10'000U);
  EXPECT_NE(run.result.reason.find("above everything the scanner looked at"), std::string::npos)
      << run.result.reason;
  // Where the robot stands is its own body's place, not a band the scanner had to see: it stays
  // green or careful, not orange for the view.
  const Eigen::Vector2i own = map.grid.cellOf(map.robot_pose.x, map.robot_pose.y);
  const CellLabel own_label = map.label(own.x(), own.y());
  EXPECT_TRUE(own_label == CellLabel::kTraversable || own_label == CellLabel::kCareful)
      << labelName(own_label);
}

TEST(AboveTheView, ARobotLowerThanTheScannerIsSeenAsFarAsItsBeamsPassOverIt) {
  SegmentationParams params;
  params.robot.height = 1.0;  // under the scanner's 1.2 m: the beams below it cover its band
  const test::SimulatedRun run = outdoorSeenWithTheAxisDown(params);
  const TraversabilityMap& map = run.result.map;
  EXPECT_GT(map.counts[std::size_t(CellLabel::kTraversable)], 5'000U);
  // Its top beam points half a degree below the horizon (the half lines' last step), and passes
  // over the band's top, 1.05 m (the headroom kept under overhangs), some 17 m out: farther, and
  // only there, the band is out of view.
  const Eigen::Vector2d scanner = run.result.analysis->map_from_scanner.translation().head<2>();
  double nearest = std::numeric_limits<double>::infinity();
  for (int row = 0; row < map.grid.height; ++row)
    for (int column = 0; column < map.grid.width; ++column)
      if (map.reasons[map.grid.index(column, row)] == std::uint8_t(CellReason::kAboveView))
        nearest = std::min(nearest, (map.grid.centre(column, row) - scanner).norm());
  EXPECT_GT(nearest, 12.0);
}

// "Can it get there?" from the robot's place to the far side of the pipe bridge (world 6.5, 0).
GoalResult goalBeyondThePipe(const test::SimulatedRun& run) {
  const Eigen::Isometry3d map_from_world =
      run.result.analysis->map_from_scanner *
      run.simulated.truth.placement.worldFromScanner().inverse();
  const Eigen::Vector3d goal = map_from_world * Eigen::Vector3d(6.5, 0.0, 0.0);
  return planPath(run.result.map, goal.x(), goal.y());
}

TEST(AboveTheView, APathUnderWhatTheScannerCouldNotSeeSaysSo) {
  // The 1.5 m robot's way under the pipe bridge the scanner never looked at: drivable only with
  // care, and the answer says how much of it.
  const test::SimulatedRun tall = outdoorSeenWithTheAxisDown(SegmentationParams{});
  const GoalResult under = goalBeyondThePipe(tall);
  ASSERT_TRUE(under.reachable) << under.reason;
  EXPECT_GT(under.length_m, 5.0);
  EXPECT_GT(under.unvouched_m, 0.8 * under.length_m);
  // A robot lower than the scanner is seen whole on the way there.
  SegmentationParams low;
  low.robot.height = 1.0;
  const GoalResult seen = goalBeyondThePipe(outdoorSeenWithTheAxisDown(low));
  ASSERT_TRUE(seen.reachable) << seen.reason;
  EXPECT_LT(seen.unvouched_m, 0.2 * seen.length_m);
  std::cout << "[ figures  ] path " << under.length_m << " m, " << under.unvouched_m
            << " m unvouched (1.5 m robot); " << seen.length_m << " m, " << seen.unvouched_m
            << " m (1.0 m robot)\n";
}

// Appends a return `polar` from the (vertical) axis, `azimuth` about it, `range` away to the scan
// and to its last line.
void addReturn(Scan& scan, double polar, double azimuth, double range) {
  const Eigen::Vector3d p =
      range * Eigen::Vector3d(std::sin(polar) * std::cos(azimuth),
                              std::sin(polar) * std::sin(azimuth), std::cos(polar));
  scan.points.push_back({float(p.x()), float(p.y()), float(p.z())});
  scan.status.push_back(PointStatus::kValid);
  ++scan.lines.back().count;
}

// A half line's ground returns, 95 to 170 deg from the axis, 1 deg apart, on the ground 1 m below.
void addGroundReturns(Scan& scan, double azimuth) {
  for (int polar_deg = 95; polar_deg <= 170; ++polar_deg)
    addReturn(scan, polar_deg * kDeg, azimuth, -1.0 / std::cos(polar_deg * kDeg));
}

// Fans at `lines` azimuths about a vertical axis, 1 m above flat ground: returns from the ground
// only, and when `with_high_return`, one return 10 deg from the axis on the first fan (a treetop).
// The file keeps returns only, as an unorganised one.
Scan groundFans(int lines, bool with_high_return) {
  Scan scan;
  for (int l = 0; l < lines; ++l) {
    const double azimuth = l * 360.0 / lines * kDeg;
    scan.lines.push_back({scan.size(), 0});
    if (with_high_return && l == 0) addReturn(scan, 10.0 * kDeg, azimuth, 8.0);
    addGroundReturns(scan, azimuth);
  }
  return scan;
}

SensorGeometry turntableOf(int lines) {
  SensorGeometry sensor;
  sensor.kind = SensorKind::kRotating2D;
  sensor.lines = std::size_t(lines);
  sensor.along_line_step = 1.0 * kDeg;
  sensor.between_line_step = 360.0 / lines * kDeg;
  sensor.closed_turn = true;
  return sensor;
}

TEST(AboveTheView, AFansAnglesWithoutAReturnAreBeamsThatWentOn) {
  constexpr int kLines = 180;
  Eigen::Isometry3d map_from_scanner = Eigen::Isometry3d::Identity();
  map_from_scanner.translation().z() = 1.0;
  const ViewLimit ground_only =
      detail::viewLimitOf(groundFans(kLines, false), turntableOf(kLines), map_from_scanner, 1);
  const ViewLimit with_treetop =
      detail::viewLimitOf(groundFans(kLines, true), turntableOf(kLines), map_from_scanner, 1);
  ASSERT_TRUE(ground_only.known());
  ASSERT_TRUE(with_treetop.known());
  for (double azimuth_deg = -175.0; azimuth_deg < 180.0; azimuth_deg += 25.0) {
    const double azimuth = azimuth_deg * kDeg;
    // Nothing rose above the horizon: the fans span 95 to 170 deg from the axis.
    EXPECT_LT(ground_only.riseAt(azimuth, 3.0), 0.0F) << azimuth_deg;
    // One return 10 deg from the axis says every fan spans that far: above its ground returns
    // each one's beams went on into the sky, steeper than 45 deg, however far.
    EXPECT_GT(with_treetop.riseAt(azimuth, 3.0), 1.0F) << azimuth_deg;
    EXPECT_GT(with_treetop.riseAt(azimuth, 50.0), 1.0F) << azimuth_deg;
  }
  // A ground return went no farther than itself: 5.7 m (the beam 100 deg from the axis) and no
  // ground return reaches 12 m (the last one, 95 deg, at 11.4 m).
  EXPECT_LT(ground_only.riseAt(0.0, 12.0), -1e30F);
}

// Half lines over a quarter turn (azimuths 0 .. 90 deg) of ground returns and a treetop on the
// first, each with one return 2 deg from the axis whose direction about it points 120 deg away:
// that close to the axis a return's side of it is noise. It must not make a side of the fan
// where no fan went, with sky beams there.
TEST(AboveTheView, AReturnBesideTheAxisMakesNoSideOfTheFan) {
  constexpr int kLines = 46;
  Scan scan;
  for (int l = 0; l < kLines; ++l) {
    const double azimuth = l * 2.0 * kDeg;
    scan.lines.push_back({scan.size(), 0});
    addReturn(scan, 2.0 * kDeg, azimuth + 120.0 * kDeg, 3.0);
    if (l == 0) addReturn(scan, 10.0 * kDeg, azimuth, 8.0);
    addGroundReturns(scan, azimuth);
  }
  SensorGeometry sensor = turntableOf(180);  // 2 deg between lines
  Eigen::Isometry3d map_from_scanner = Eigen::Isometry3d::Identity();
  map_from_scanner.translation().z() = 1.0;
  const ViewLimit view = detail::viewLimitOf(scan, sensor, map_from_scanner, 1);
  ASSERT_TRUE(view.known());
  EXPECT_GT(view.riseAt(45.0 * kDeg, 3.0), 1.0F);  // where the fans went: their sky beams
  for (double azimuth_deg = 130.0; azimuth_deg <= 330.0; azimuth_deg += 20.0)
    EXPECT_LT(view.riseAt(azimuth_deg * kDeg, 3.0), 1.0F) << azimuth_deg;
}

}  // namespace
}  // namespace clearway
