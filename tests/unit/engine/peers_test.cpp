// The benchmark's peers are only as honest as their adapters: each must find the planes of a
// simple scene (a broken adapter would flatter our figures) and must not crash on scans it
// cannot use.

#include <gtest/gtest.h>

#include <algorithm>

#include "clearway/eval/segmentation_accuracy.h"
#include "clearway/peers/plane_peers.h"
#include "clearway/peers/traversability_peer.h"
#include "engine_fixtures.h"

namespace clearway {
namespace {

RobotParams robotOfWidth(double width) {
  RobotParams robot;
  robot.width = width;
  return robot;
}

SegmentationParams paramsFor(const RobotParams& robot) {
  SegmentationParams params;
  params.robot = robot;
  return params;
}

TEST(PlanePeers, EachFindsTheGaragePlanesOnTheirTrueSurfaces) {
  const auto run = test::simulateAndSegment("garage", 120);
  const Scan& scan = run.simulated.scan;
  for (const peers::PlanePeer& peer : peers::planePeers()) {
    SCOPED_TRACE(peer.name);
    ASSERT_TRUE(peer.unsuitable(scan).empty()) << peer.unsuitable(scan);
    const eval::PointPlanes result = peer.run(scan, 2, {});
    ASSERT_EQ(result.point_plane.size(), scan.size());
    const eval::SegmentationAccuracy accuracy =
        eval::scoreSegmentation(run.simulated.truth, result);
    EXPECT_GE(accuracy.planes.recall, 0.6);
    EXPECT_GT(accuracy.point_purity, 0.9);
    EXPECT_GT(accuracy.coverage, 0.3);
    EXPECT_LT(accuracy.planes.mean_normal_error_deg, 2.0);
    for (std::size_t i = 0; i < scan.size(); ++i) {
      if (!scan.isValid(i)) {
        ASSERT_EQ(result.point_plane[i], -1) << "invalid point " << i;
      }
    }
  }
}

TEST(PlanePeers, ScansTheyCannotUseGiveAReasonOrNoPlanes) {
  Scan ragged = test::simulateAndSegment("garage", 40).simulated.scan;
  // Drop the last point of the last line: the lines are no longer of equal length.
  ragged.points.pop_back();
  ragged.status.pop_back();
  ragged.intensity.resize(std::min(ragged.intensity.size(), ragged.points.size()));
  ragged.alpha.resize(std::min(ragged.alpha.size(), ragged.points.size()));
  --ragged.lines.back().count;
  ASSERT_FALSE(ragged.isOrganised());
  const auto& organised = peers::planePeers().front();
  EXPECT_NE(organised.unsuitable(ragged).find("organised"), std::string::npos);

  Scan nothing = test::simulateAndSegment("garage", 40).simulated.scan;
  std::fill(nothing.status.begin(), nothing.status.end(), PointStatus::kNoReturn);
  for (const peers::PlanePeer& peer : peers::planePeers()) {
    SCOPED_TRACE(peer.name);
    const eval::PointPlanes result = peer.run(nothing, 2, {});
    EXPECT_TRUE(result.planes.empty());
    EXPECT_EQ(result.point_plane.size(), nothing.size());
  }
}

std::size_t countLabel(const std::vector<std::uint8_t>& labels, CellLabel label) {
  return std::size_t(std::count(labels.begin(), labels.end(), std::uint8_t(label)));
}

TEST(TraversabilityPeer, FitsTheRobotOnlyOnObservedFreeGroundAndNotWhenTooWide) {
  const RobotParams small = robotOfWidth(0.85);
  const auto run = test::simulateAndSegment("garage", 200, paramsFor(small));
  const ScanAnalysis& analysis = *run.result.analysis;
  const auto labels =
      peers::dilateTraversability(analysis, small, MapParams{}, run.result.map.yaws, 2);
  ASSERT_EQ(labels.size(), run.result.map.labels.size());
  const std::size_t fits = countLabel(labels, CellLabel::kTraversable);
  EXPECT_GT(fits, 1000u);
  for (std::size_t cell = 0; cell < labels.size(); ++cell) {
    // Unobserved stays unknown, and a cell our map calls a wall is never free for the peer.
    const auto ours = CellLabel(run.result.map.labels[cell]);
    const auto why = CellReason(run.result.map.reasons[cell]);
    if (ours == CellLabel::kUnknown && why != CellReason::kUnseenAround) {
      ASSERT_EQ(labels[cell], 0) << cell;
    }
    if (why == CellReason::kWall) {
      ASSERT_NE(labels[cell], std::uint8_t(CellLabel::kTraversable)) << cell;
    }
  }
  // A wider robot fits in fewer places; one wider than the garage fits nowhere inside it.
  const auto wide =
      peers::dilateTraversability(analysis, robotOfWidth(1.6), MapParams{}, run.result.map.yaws, 2);
  EXPECT_LT(countLabel(wide, CellLabel::kTraversable), fits);
  const auto huge = peers::dilateTraversability(analysis, robotOfWidth(30.0), MapParams{},
                                                run.result.map.yaws, 2);
  EXPECT_EQ(countLabel(huge, CellLabel::kTraversable), 0u);
}

TEST(TraversabilityPeer, WithoutGroundNothingIsTraversable) {
  const auto run = test::simulateAndSegment("no-ground", 80);
  ASSERT_FALSE(run.result.analysis->ground_found);
  const auto labels =
      peers::dilateTraversability(*run.result.analysis, RobotParams{}, MapParams{}, {0.0}, 2);
  EXPECT_EQ(countLabel(labels, CellLabel::kTraversable), 0u);
}

}  // namespace
}  // namespace clearway
