// Reasons that are true: when no ground is found the reason names the cause (a ceiling-only scan,
// one scan line, a scan without pose, a floor that failed validation, too few points), and a scan
// too sparse to vouch for any cell says so instead of showing green.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "clearway/pipeline.h"
#include "clearway/sensor_geometry.h"
#include "engine_fixtures.h"

namespace clearway {
namespace {

// A RoSi-like turn of `lines` half lines (alpha 0.5 .. 89.5 deg up from the horizon about z)
// whose beams end where they meet the plane z = `plane_height`, within 20 m; others are no-returns.
Scan fansAgainstPlane(int lines, double plane_height) {
  Scan scan;
  constexpr int kPointsPerLine = 180;
  for (int l = 0; l < lines; ++l) {
    const double beta = 2.0 * std::numbers::pi * l / lines;
    scan.lines.push_back({scan.points.size(), kPointsPerLine, beta});
    for (int k = 0; k < kPointsPerLine; ++k) {
      const double alpha = (0.5 + 0.5 * k) * std::numbers::pi / 180.0;
      const double range = plane_height / std::sin(alpha);
      const bool hit = range > 0 && range < 20.0;
      const double r = hit ? range : 0.0;
      scan.points.push_back({float(std::cos(beta) * std::cos(alpha) * r),
                             float(std::sin(beta) * std::cos(alpha) * r),
                             float(std::sin(alpha) * r)});
      scan.status.push_back(hit ? PointStatus::kValid : PointStatus::kNoReturn);
    }
  }
  return scan;
}

TEST(NoGroundReason, ACeilingOnlyScanSaysTheOnlyFlatPlanesAreAboveTheScanner) {
  const Scan scan = fansAgainstPlane(120, 2.5);
  ASSERT_GT(scan.validCount(), 1000u);
  const PipelineResult result = runPipeline(scan, SegmentationParams{});
  EXPECT_FALSE(result.trusted());
  EXPECT_NE(result.reason.find("above the scanner"), std::string::npos) << result.reason;
  EXPECT_EQ(result.map.counts[std::size_t(CellLabel::kTraversable)], 0u);
}

TEST(NoGroundReason, ASingleLineSaysSo) {
  // One horizontal line of 2,000 returns on a wall 3 m away (a 2D scan, or a multi-beam frame
  // whose rings were not recovered).
  Scan scan;
  scan.lines.push_back({0, 2000});
  for (int k = 0; k < 2000; ++k) {
    const double azimuth = -0.8 + 1.6 * k / 2000.0;
    scan.points.push_back({3.0F, float(3.0 * std::tan(azimuth)), -0.5F});
    scan.status.push_back(PointStatus::kValid);
  }
  const PipelineResult result = runPipeline(scan, SegmentationParams{});
  EXPECT_FALSE(result.trusted());
  EXPECT_NE(result.reason.find("one scan line"), std::string::npos) << result.reason;
  EXPECT_EQ(result.reason.find("move the robot"), std::string::npos);
}

TEST(NoGroundReason, AScanWithoutPoseSaysSoAndDoesNotAdviseMovingTheArm) {
  // The garage as an acquisition without a pose writes it, and estimating the up direction off
  // (--up none): nothing tells which way is up, and the reason says that, not "move the arm".
  const auto run = test::simulateAndSegment("garage", 80);
  Scan bare = run.simulated.scan;
  bare.sensor_pose.reset();
  bare.pose_source = PoseSource::kNone;
  SegmentationParams params;
  params.ground.estimate_up = 0;
  const PipelineResult result = runPipeline(bare, params);
  EXPECT_FALSE(result.trusted());
  EXPECT_NE(result.analysis->reason.find("no pose"), std::string::npos) << result.analysis->reason;
  EXPECT_NE(result.analysis->reason.find("--pose"), std::string::npos) << result.analysis->reason;
  EXPECT_EQ(result.analysis->reason.find("move"), std::string::npos) << result.analysis->reason;
  EXPECT_EQ(result.map.counts[std::size_t(CellLabel::kTraversable)], 0u);
  // With its pose the same scan finds its ground.
  EXPECT_TRUE(run.result.trusted()) << run.result.analysis->reason;
}

TEST(NoGroundReason, AFloorThatFailedValidationSaysSoWithWhatWasMeasured) {
  // The garage's floor is in view; held to limits no plane meets, the support test removes it.
  // The reason says a floor was seen and which limit it failed, not that the floor is out of view.
  const auto run = test::simulateAndSegment("garage", 200);
  ASSERT_TRUE(run.result.trusted()) << run.result.reason;
  auto refusedWith = [&](const SegmentationParams& params) {
    const PipelineResult result = runPipeline(run.simulated.scan, params);
    EXPECT_FALSE(result.trusted());
    EXPECT_EQ(result.map.counts[std::size_t(CellLabel::kTraversable)], 0u);
    return result.analysis->reason;
  };
  SegmentationParams not_flat;
  not_flat.validation.min_inner_fraction = 0.99;
  const std::string flat_reason = refusedWith(not_flat);
  EXPECT_NE(flat_reason.find("a floor candidate was seen"), std::string::npos) << flat_reason;
  EXPECT_NE(flat_reason.find("inner fraction"), std::string::npos) << flat_reason;
  EXPECT_NE(flat_reason.find("0.99 needed"), std::string::npos) << flat_reason;
  EXPECT_EQ(flat_reason.find("out of view"), std::string::npos) << flat_reason;

  SegmentationParams too_small;
  too_small.validation.min_area = 500.0;
  const std::string small_reason = refusedWith(too_small);
  EXPECT_NE(small_reason.find("supported area"), std::string::npos) << small_reason;
  EXPECT_NE(small_reason.find("500.00 m2 needed"), std::string::npos) << small_reason;
  EXPECT_EQ(small_reason.find("inner fraction"), std::string::npos) << small_reason;
}

TEST(NoGroundReason, TooFewPointsSaysSo) {
  Scan scan = fansAgainstPlane(4, -1.0);
  const PipelineResult result = runPipeline(scan, SegmentationParams{});
  EXPECT_FALSE(result.trusted());
  EXPECT_NE(result.reason.find("too sparse"), std::string::npos) << result.reason;
}

TEST(SparseScan, FewLinesShowOrangeWithTheReasonTooSparse) {
  // At 40 lines (9 deg between lines) a 0.1 m step is vouched for only near the turntable axis.
  const auto run = test::simulateAndSegment("hallway", 40);
  ASSERT_TRUE(run.result.trusted()) << run.result.reason;
  std::size_t sparse = 0;
  for (std::size_t cell = 0; cell < run.result.map.labels.size(); ++cell)
    if (run.result.map.reasons[cell] == std::uint8_t(CellReason::kSparse)) {
      ++sparse;
      EXPECT_EQ(run.result.map.labels[cell], std::uint8_t(CellLabel::kObstacle));
    }
  EXPECT_GT(sparse, 100u);
  // At 423 lines the same hallway is vouched for everywhere but at the stairs' foot, where the
  // risers standing off the lower floor cast their shadows (6 cells; docs/ALGORITHM.md, "Sparse
  // scans never lie").
  const auto dense = test::simulateAndSegment("hallway", 423);
  EXPECT_LT(std::count(dense.result.map.reasons.begin(), dense.result.map.reasons.end(),
                       std::uint8_t(CellReason::kSparse)),
            sparse / 20);
}

TEST(SparseScan, NothingVouchedForSaysTooSparse) {
  // A robot that takes no step worth the name (2 cm): no sample spacing vouches for any cell.
  SegmentationParams params;
  params.robot.max_step = 0.02;
  const auto run = test::simulateAndSegment("garage", 80, params);
  ASSERT_TRUE(run.result.trusted()) << run.result.reason;
  EXPECT_EQ(run.result.map.counts[std::size_t(CellLabel::kTraversable)], 0u);
  EXPECT_NE(run.result.reason.find("too sparse"), std::string::npos) << run.result.reason;
  // The reason is the robot's, not the analysis': a robot whose step the same scan vouches for
  // gets green cells and no "too sparse" (the shared analysis keeps no earlier robot's reason).
  EXPECT_EQ(run.result.analysis->reason, "");
  const PipelineResult usual = rerunForRobot(run.simulated.scan, run.result.analysis, {});
  EXPECT_GT(usual.map.counts[std::size_t(CellLabel::kTraversable)], 0u);
  EXPECT_EQ(usual.reason, "");
}

TEST(SparseScan, ExpectedGroundSpacingGrowsWithRangeAndFewerLines) {
  SensorGeometry rosi;
  rosi.kind = SensorKind::kRotating2D;
  rosi.along_line_step = 0.5 * std::numbers::pi / 180.0;
  rosi.between_line_step = 2.0 * std::numbers::pi / 423;
  const double near = expectedGroundSpacing(rosi, 2.0, 1.2);
  const double far = expectedGroundSpacing(rosi, 8.0, 1.2);
  EXPECT_LT(near, far);
  SensorGeometry sparse = rosi;
  sparse.between_line_step = 2.0 * std::numbers::pi / 40;
  EXPECT_NEAR(expectedGroundSpacing(sparse, 4.0, 1.2), 4.0 * sparse.between_line_step, 1e-9);
  EXPECT_TRUE(std::isinf(expectedGroundSpacing(rosi, 4.0, 0.0)));
}

}  // namespace
}  // namespace clearway
