// The real scans in ../shared/data/real (see its README): counts and structure each loader must
// recover. Skipped with a message when the folder is absent.

#include <gtest/gtest.h>

#include <cmath>

#include "clearway/io/scan_io.h"
#include "test_support.h"

namespace clearway {
namespace {

TEST(RealScans, PclRoomScanHas636ReconstructedLinesAndSelfHitsMarked) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, "pcl-room/room_scan1.pcd");
  const Scan scan = loadScan(file);
  EXPECT_EQ(scan.size(), 112586u);
  EXPECT_EQ(scan.lines.size(), 636u);
  EXPECT_LE(scan.pointsPerLine(), 181u + 30u);
  const std::size_t self_hits =
      std::count(scan.status.begin(), scan.status.end(), PointStatus::kSelfHit);
  // SOURCE.txt: ~20.4k points within 0.3 m of the sensor.
  EXPECT_GT(self_hits, 19000u);
  EXPECT_LT(self_hits, 22000u);
  // Floor 1.27 m below the scanner, ceiling at +1.65 m.
  const Bounds bounds = validBounds(scan);
  EXPECT_NEAR(bounds.min.z, -1.3, 0.1);
}

TEST(RealScans, OctomapStairsHas491Lines) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, "octomap-stairs/scan.dat");
  const Scan scan = loadScan(file);
  EXPECT_EQ(scan.size(), 88206u);
  EXPECT_EQ(scan.lines.size(), 491u);
  EXPECT_LE(scan.pointsPerLine(), 181u);
}

TEST(RealScans, ThreeDtkScanIsOrganised226By360WithInvalidReturnsKept) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, "3dtk/scan000.3d");
  const Scan scan = loadScan(file);
  EXPECT_EQ(scan.size(), 81360u);
  EXPECT_EQ(scan.lines.size(), 226u);
  EXPECT_TRUE(scan.isOrganised());
  EXPECT_EQ(scan.pointsPerLine(), 360u);
  const auto count = [&](PointStatus status) {
    return std::size_t(std::count(scan.status.begin(), scan.status.end(), status));
  };
  // SOURCE.txt: ~1.3-1.7k max-range points, ~1.7-2.0k near-zero/self points per scan.
  EXPECT_GT(count(PointStatus::kMaxRange), 1200u);
  EXPECT_LT(count(PointStatus::kMaxRange), 1800u);
  EXPECT_GT(count(PointStatus::kSelfHit), 1600u);
  EXPECT_LT(count(PointStatus::kSelfHit), 2100u);
  // The floor is ~0.4 m below the scanner; converted to z up.
  int floor_points = 0;
  for (std::size_t i = 0; i < scan.size(); ++i)
    if (scan.isValid(i) && std::abs(scan.points[i].z + 0.39F) < 0.03F) ++floor_points;
  EXPECT_GT(floor_points, 5000);
}

TEST(RealScans, HannoverScansHaveVerticalFansAndAPose) {
  for (const char* name : {"hannover1/scan100.3d", "hannover1/scan440.3d"}) {
    CLEARWAY_REAL_SCAN_OR_SKIP(file, name);
    SCOPED_TRACE(name);
    const Scan scan = loadScan(file);
    EXPECT_GT(scan.size(), 18000u);
    // The origin is at ground level, so fan ends are ambiguous (docs/FORMATS.md): between the
    // "jumps back" count and the "jumps either way" count.
    EXPECT_GE(scan.lines.size(), 150u);
    EXPECT_LE(scan.lines.size(), 260u);
    EXPECT_LE(scan.pointsPerLine(), 450u);
    ASSERT_TRUE(scan.sensor_pose.has_value());
    // Ground points sit near z = 0.
    const Bounds bounds = validBounds(scan);
    EXPECT_NEAR(bounds.min.z, -0.35, 0.1);
  }
}

}  // namespace
}  // namespace clearway
