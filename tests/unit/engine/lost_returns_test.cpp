// Returns the scanner lost (dark or wet ground, puddles, dust): the ground triangles bridge up to
// kLostReturnsBridged of them in a row, the density check counts the wider spacing there, and a
// longer run stays unobserved. Scenes from the simulator, whose --dropout loses returns at random.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "../../../core/src/segmentation/ground_triangles.h"
#include "clearway/eval/evaluation.h"
#include "clearway/sensor_geometry.h"
#include "engine_fixtures.h"

namespace clearway {
namespace {

sim::SimulatedScan simulated(const std::string& scene_name, double dropout) {
  const sim::Scene scene = *sim::builtinScene(scene_name, {});
  sim::SensorModel sensor;
  sensor.dropout = dropout;
  return sim::simulateRosi(scene, sensor, sim::defaultPlacement(scene));
}

// Green, careful and probably passable cells: what the map shows the robot may use.
std::size_t shownCells(const TraversabilityMap& map) {
  return map.counts[std::size_t(CellLabel::kTraversable)] +
         map.counts[std::size_t(CellLabel::kCareful)] +
         map.counts[std::size_t(CellLabel::kObstacle)];
}

// The simulator loses returns from a generator of its own: the returns it keeps are the ones the
// scan without losses has, to the bit, and about the share asked for is lost.
TEST(LostReturns, TheSimulatorLosesReturnsAndKeepsTheRest) {
  const sim::SimulatedScan whole = simulated("garage", 0.0);
  const sim::SimulatedScan lossy = simulated("garage", 0.2);
  ASSERT_EQ(whole.scan.size(), lossy.scan.size());
  std::size_t returns = 0, lost = 0;
  for (std::size_t i = 0; i < whole.scan.size(); ++i) {
    if (!whole.scan.isValid(i)) {
      EXPECT_FALSE(lossy.scan.isValid(i));
      continue;
    }
    ++returns;
    if (!lossy.scan.isValid(i)) {
      ++lost;
      EXPECT_EQ(lossy.truth.classes[i], PointClass::kNone);
      continue;
    }
    EXPECT_EQ(lossy.scan.points[i].x, whole.scan.points[i].x);
    EXPECT_EQ(lossy.scan.points[i].z, whole.scan.points[i].z);
  }
  EXPECT_NEAR(double(lost) / double(returns), 0.2, 0.01);
}

// A fifth of the returns lost: no false-traversable cell, and most of what the whole scan shows
// still shown (0.68, 0.64, 0.76 of it; 0.48, 0.24, 0.33 when a triangle needed all three corners).
class FifthLost : public ::testing::TestWithParam<const char*> {};

TEST_P(FifthLost, TheFloorIsStillShownAndNothingFalse) {
  const std::string scene = GetParam();
  test::SimulatedRun whole, lossy;
  whole.simulated = simulated(scene, 0.0);
  whole.result = runPipeline(whole.simulated.scan, SegmentationParams{});
  lossy.simulated = simulated(scene, 0.2);
  lossy.result = runPipeline(lossy.simulated.scan, SegmentationParams{});
  ASSERT_TRUE(lossy.result.trusted()) << lossy.result.reason;
  EXPECT_EQ(test::evaluateRun(lossy).map.false_traversable_cells, 0u);
  const double kept = double(shownCells(lossy.result.map)) / double(shownCells(whole.result.map));
  std::cout << "[ figures  ] " << scene << ", a fifth of the returns lost: " << kept
            << " of the cells shown without losses still shown\n";
  EXPECT_GE(kept, 0.6);
}

INSTANTIATE_TEST_SUITE_P(Scenes, FifthLost, ::testing::Values("garage", "doorways", "outdoor"));

// The scan with every return lost but one in `period` along each line: runs of period - 1 lost.
Scan keepingOneIn(const Scan& scan, std::size_t period) {
  Scan kept = scan;
  for (const ScanLine& line : scan.lines)
    for (std::size_t k = 0; k < line.count; ++k)
      if (k % period != 0 && kept.isValid(line.first + k))
        kept.status[line.first + k] = PointStatus::kNoReturn;
  return kept;
}

// Two lost in a row are bridged; three are not (an obstacle that loses every return, a black one,
// may be that wide): the floor between the returns left is unobserved, only the cells holding them
// are ground (3,707 cells shown with two of three lost, 770 with three of four, 5,651 with none).
TEST(LostReturns, TwoInARowAreBridgedThreeAreNot) {
  const sim::SimulatedScan garage = simulated("garage", 0.0);
  const PipelineResult whole = runPipeline(garage.scan, SegmentationParams{});
  ASSERT_EQ(detail::kLostReturnsBridged, 2u);
  const PipelineResult two_lost = runPipeline(keepingOneIn(garage.scan, 3), SegmentationParams{});
  const PipelineResult three_lost = runPipeline(keepingOneIn(garage.scan, 4), SegmentationParams{});
  const double whole_shown = double(shownCells(whole.map));
  std::cout << "[ figures  ] garage: " << shownCells(two_lost.map) << " cells shown with two of "
            << "three returns lost, " << shownCells(three_lost.map) << " with three of four, "
            << whole_shown << " with none\n";
  EXPECT_GE(double(shownCells(two_lost.map)), 0.5 * whole_shown);
  EXPECT_LE(double(shownCells(three_lost.map)), 0.2 * whole_shown);
}

// Where triangles bridge lost returns, the ground samples lie farther apart along the line: the
// spacing the density check compares with the robot's step grows there (where the step along the
// line is what could hide an obstacle), cell by cell as much as the two runs' slightly different
// ground planes let the cells be compared.
TEST(LostReturns, BridgedGroundCountsAsSparser) {
  const sim::SimulatedScan garage = simulated("garage", 0.0);
  const PipelineResult whole = runPipeline(garage.scan, SegmentationParams{});
  const PipelineResult half = runPipeline(keepingOneIn(garage.scan, 2), SegmentationParams{});
  const MapInputs& a = whole.analysis->inputs;
  const MapInputs& b = half.analysis->inputs;
  ASSERT_EQ(a.grid.width, b.grid.width);
  ASSERT_EQ(a.grid.height, b.grid.height);
  std::vector<double> ratios;
  for (std::size_t cell = 0; cell < a.grid.cells(); ++cell) {
    if (a.ground_plane[cell] < 0 || b.ground_plane[cell] < 0) continue;
    if (!std::isfinite(a.ground_spacing[cell]) || !std::isfinite(b.ground_spacing[cell])) continue;
    ratios.push_back(double(b.ground_spacing[cell]) / double(a.ground_spacing[cell]));
  }
  ASSERT_GT(ratios.size(), 1000u);
  std::sort(ratios.begin(), ratios.end());
  const double low = ratios[ratios.size() / 20], median = ratios[ratios.size() / 2];
  std::cout << "[ figures  ] every second return lost: spacing " << low << " (5th percentile), "
            << median << " (median) times the whole scan's\n";
  EXPECT_GT(median, 1.3);
  EXPECT_GT(low, 0.95);
}

// A file of rings that keeps only the returns shows a lost one only as a gap in its ring's
// azimuths. Two rings 1 deg between returns, 5 and 5.5 m out on flat ground: the first lost one
// return at 50 deg and five from 100 deg (a black box 0.45 m wide, well within the triangles'
// 1 m edge limit), the second keeps two returns out of azimuth order (200 and 203 deg swapped, as a
// frame corrected for the vehicle's motion keeps some). Units of the stage: LinePairing's gaps and
// the ground triangles over them.
TEST(LostReturns, ARaggedRingsGapIsBridgedOnlyUpToTwoLostReturns) {
  constexpr double kDegree = std::numbers::pi / 180.0;
  constexpr float kHeight = 1.7F;
  Scan scan;
  SensorGeometry sensor;
  sensor.kind = SensorKind::kMultiBeam;
  sensor.lines = 2;
  sensor.along_line_step = kDegree;
  for (const double range : {5.0, 5.5}) {
    ScanLine ring{scan.points.size(), 0, std::nan("")};
    std::vector<int> azimuths;
    for (int a = 0; a < 360; ++a) {
      const bool lost = range == 5.0 && (a == 50 || (a >= 100 && a < 105));
      if (!lost) azimuths.push_back(a);
    }
    if (range == 5.5)
      std::swap(*std::find(azimuths.begin(), azimuths.end(), 200),
                *std::find(azimuths.begin(), azimuths.end(), 203));
    for (const int a : azimuths) {
      scan.points.push_back(
          {float(range * std::cos(a * kDegree)), float(range * std::sin(a * kDegree)), -kHeight});
      scan.status.push_back(PointStatus::kValid);
    }
    ring.count = scan.points.size() - ring.first;
    scan.lines.push_back(ring);
    sensor.line_angle.push_back(std::atan2(-kHeight, range));
  }
  sensor.between_line_step = std::abs(sensor.line_angle[1] - sensor.line_angle[0]);
  const std::vector<std::int32_t> ground_of(scan.size(), 0);
  const detail::LinePairing pairing(scan, ground_of, sensor, kHeight, 1);
  ASSERT_TRUE(pairing.raggedRings());
  EXPECT_NEAR(pairing.widestGap(scan.lines[0], 99.5 * kDegree, 104.5 * kDegree, 1.0), 6 * kDegree,
              1e-4);
  EXPECT_NEAR(pairing.widestGap(scan.lines[1], 199.5 * kDegree, 203.5 * kDegree, 1.0), kDegree,
              1e-4);

  std::vector<Eigen::Vector3f> mapped;
  for (const Point3f& p : scan.points)
    mapped.emplace_back(p.x, p.y, p.z);
  const detail::EdgeLimit limit{mapped, sensor, 1.0, kHeight};
  std::vector<detail::BridgedTriangle> bridged;
  const auto triangles =
      detail::groundTriangles(scan, pairing, ground_of, limit, 1, nullptr, &bridged);
  // The azimuths a triangle's corners span [deg].
  auto span = [&](const std::array<std::uint32_t, 3>& t) {
    std::array<double, 3> a{};
    for (std::size_t c = 0; c < 3; ++c) {
      const Point3f& p = scan.points[t[c]];
      a[c] = std::atan2(p.y, p.x) / kDegree;
      if (a[c] < 0) a[c] += 360.0;
    }
    return std::pair{*std::min_element(a.begin(), a.end()), *std::max_element(a.begin(), a.end())};
  };
  std::size_t across_the_box = 0, across_the_swap = 0, across_the_single = 0;
  for (const auto& t : triangles) {
    const auto [low, high] = span(t);
    across_the_box += low < 102.5 && high > 102.5;
    across_the_swap += low < 201.5 && high > 201.5;
    across_the_single += low < 50.0 && high > 50.0;
  }
  EXPECT_EQ(across_the_box, 0U);
  EXPECT_GT(across_the_swap, 0U);
  EXPECT_GT(across_the_single, 0U);
  // The gap of one lost return is bridged with its samples two steps apart.
  EXPECT_TRUE(std::any_of(bridged.begin(), bridged.end(), [&](const detail::BridgedTriangle& b) {
    const auto [low, high] = span(b.corners);
    return low < 50.0 && high > 50.0 && b.steps_apart == 2;
  }));
}

}  // namespace
}  // namespace clearway
