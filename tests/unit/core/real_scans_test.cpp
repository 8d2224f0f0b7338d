// The real scans in ../shared/data/real (see its README): counts and structure each loader must
// recover. Skipped with a message when the folder is absent.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "clearway/io/scan_io.h"
#include "clearway/sensor_geometry.h"
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

// The nodding scanners' fans all point forward: their directions about z told them apart by
// noise alone (3DTK's step between lines read 0.021 deg, octomap's 0.052), and the ground was
// triangulated between fans far apart. They are ordered by their tilt about the axis they hold:
// 3DTK's from -48.7 to +67.6 deg in 0.517 deg steps (SOURCE.txt); octomap's, each a plane to
// within millimetres half a metre from the file's origin, from +30.0 to -54.8 deg, slowly at
// first (our fit; its SOURCE.txt guessed +24 to -4 deg).
TEST(RealScans, NoddingScannersFansLieSideBySideByTheirTilt) {
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  struct Case {
    const char* name;
    double sweep_deg;
    double step_deg;  // 0: the tilt's steps vary
  };
  for (const Case& c :
       {Case{"3dtk/scan000.3d", 116.3, 0.517}, Case{"octomap-stairs/scan.dat", 84.8, 0.0}}) {
    CLEARWAY_REAL_SCAN_OR_SKIP(file, c.name);
    SCOPED_TRACE(c.name);
    const Scan scan = loadScan(file);
    const SensorGeometry sensor = describeSensor(scan);
    ASSERT_EQ(sensor.kind, SensorKind::kRotating2D);
    EXPECT_FALSE(sensor.closed_turn);
    // Neighbours in the file are neighbours by angle: the angle runs one way from the first fan
    // to the last, over the whole tilt.
    std::vector<double> steps;
    for (std::size_t l = 1; l < sensor.line_angle.size(); ++l)
      if (std::isfinite(sensor.line_angle[l - 1]) && std::isfinite(sensor.line_angle[l]))
        steps.push_back(sensor.line_angle[l] - sensor.line_angle[l - 1]);
    ASSERT_GT(steps.size(), 200u);
    double sweep = 0.0;
    std::size_t back = 0;
    for (const double step : steps)
      sweep += step;
    for (const double step : steps)
      back += step * sweep < 0.0 && std::abs(step) > 0.05 * kDeg;
    EXPECT_NEAR(std::abs(sweep) / kDeg, c.sweep_deg, 1.0);
    EXPECT_EQ(back, 0u);
    if (c.step_deg > 0.0) {
      EXPECT_NEAR(sensor.between_line_step / kDeg, c.step_deg, 0.005);
    }
  }
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
