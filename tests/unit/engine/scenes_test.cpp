// What the issue asks the engine to show on the other scenes and on real scans.

#include <gtest/gtest.h>

#include <cmath>

#include "clearway/io/scan_io.h"
#include "engine_fixtures.h"
#include "test_support.h"

namespace clearway {
namespace {

bool green(CellLabel label) {
  return label == CellLabel::kTraversable;
}
bool greenOrOrange(CellLabel label) {
  return label == CellLabel::kTraversable || label == CellLabel::kCareful;
}

TEST(Hallway, FloorAndRampAreGroundTheStairsAreNot) {
  const auto run = test::simulateAndSegment("hallway", 300);
  ASSERT_TRUE(run.result.trusted());
  // Two ground planes are accepted: the floor and the 12 degree ramp.
  int ramp_planes = 0;
  const Eigen::Vector3d up = run.result.analysis->up;
  for (int g : run.result.map.accepted_ground) {
    const double slope =
        std::acos(std::abs(run.result.analysis->planes.planes[std::size_t(g)].normal.dot(up))) *
        180 / M_PI;
    if (std::abs(slope - 12.0) < 1.0) ++ramp_planes;
  }
  EXPECT_EQ(ramp_planes, 1);
  EXPECT_TRUE(green(test::labelAtWorld(run, {1.0, 0.0, 0.0}))) << "lower floor";
  EXPECT_TRUE(green(test::labelAtWorld(run, {4.5, 0.8, 0.3}))) << "on the ramp";
  // No cell on the stairs lane is green or orange.
  for (double x = 3.05; x < 3.0 + 4 * 0.29; x += 0.05)
    for (double y = -1.45; y < -0.1; y += 0.05)
      EXPECT_FALSE(greenOrOrange(test::labelAtWorld(run, {x, y, 0.0})))
          << "stairs at " << x << ", " << y;
}

TEST(NoGround, AScanThatNeverSeesTheFloorShowsNothingTraversable) {
  const auto run = test::simulateAndSegment("no-ground", 200);
  EXPECT_FALSE(run.result.trusted());
  EXPECT_FALSE(run.result.reason.empty());
  EXPECT_NE(run.result.reason.find("no ground plane"), std::string::npos);
  EXPECT_EQ(run.result.map.counts[std::size_t(CellLabel::kTraversable)], 0u);
  EXPECT_EQ(run.result.map.counts[std::size_t(CellLabel::kCareful)], 0u);
  EXPECT_EQ(run.result.map.counts[std::size_t(CellLabel::kObstacle)], 0u);
  EXPECT_TRUE(run.result.scene.triangles.empty());
}

TEST(Glass, NothingIsTraversableBeyondAnInvisibleGlassWall) {
  const auto run = test::simulateAndSegment("glass", 300);
  ASSERT_TRUE(run.result.trusted());
  EXPECT_TRUE(green(test::labelAtWorld(run, {2.0, 0.0, 0.0})));
  // The robot (0.85 m wide, 1.2 m long) cannot stand closer than half its width to the glass it
  // cannot see: the open edge of what was observed blocks.
  for (double x = 3.6; x < 6.0; x += 0.1)
    EXPECT_FALSE(greenOrOrange(test::labelAtWorld(run, {x, 0.0, 0.0}))) << "x = " << x;
}

TEST(RealScans, TheRoomFloorIsFound) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, "pcl-room/room_scan1.pcd");
  const PipelineResult result = runPipeline(loadScan(file), {});
  ASSERT_TRUE(result.trusted()) << result.reason;
  const Plane& floor =
      result.analysis->planes.planes[std::size_t(result.analysis->reference_ground)];
  // SOURCE.txt: the floor is at z = -1.27 m below the scanner.
  EXPECT_NEAR(std::abs(floor.normal.z()), 1.0, 0.01);
  EXPECT_NEAR(floor.offset, 1.27, 0.05);
  EXPECT_GT(result.map.counts[std::size_t(CellLabel::kTraversable)], 500u);
}

TEST(RealScans, OctomapPavedGroundIsGreenAndTheStaircaseIsNot) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, "octomap-stairs/scan.dat");
  const PipelineResult result = runPipeline(loadScan(file), {});
  ASSERT_TRUE(result.trusted()) << result.reason;
  auto labelAt = [&](double x, double y) {
    const Eigen::Vector3d m = result.analysis->map_from_scanner * Eigen::Vector3d(x, y, -0.15);
    const Eigen::Vector2i cell = result.map.grid.cellOf(m.x(), m.y());
    return result.map.grid.inside(cell.x(), cell.y()) ? result.map.label(cell.x(), cell.y())
                                                      : CellLabel::kUnknown;
  };
  // SOURCE.txt: the stairs start at x ~ 5.1 m and fill y ~ -3 .. 3 m; paved ground in front.
  int paved_green = 0, paved = 0;
  for (double x = 2.0; x <= 4.0; x += 0.25)
    for (double y = -1.5; y <= 1.5; y += 0.25, ++paved)
      paved_green += green(labelAt(x, y));
  EXPECT_GT(paved_green, paved * 3 / 4);
  for (double x = 5.6; x <= 9.0; x += 0.1)
    for (double y = -2.5; y <= 2.5; y += 0.1)
      EXPECT_FALSE(greenOrOrange(labelAt(x, y))) << "stairs at " << x << ", " << y;
}

}  // namespace
}  // namespace clearway
