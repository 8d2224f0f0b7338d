#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "clearway/io/scan_lines.h"

namespace clearway {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Vertical half lines like the PCL room scan: elevation sweeps +80 -> -80 deg at a fixed azimuth.
Scan verticalFans(int fans, int points_per_fan) {
  Scan scan;
  for (int f = 0; f < fans; ++f) {
    const double azimuth = f * 2.0 * kDeg;
    for (int k = 0; k < points_per_fan; ++k) {
      const double elevation = (80.0 - 160.0 * k / (points_per_fan - 1)) * kDeg;
      const double range = 3.0 + 0.5 * std::sin(k * 0.1);
      scan.points.push_back({float(range * std::cos(elevation) * std::cos(azimuth)),
                             float(range * std::cos(elevation) * std::sin(azimuth)),
                             float(range * std::sin(elevation))});
      scan.status.push_back(PointStatus::kValid);
    }
  }
  return scan;
}

// Horizontal fans like the octomap scan: azimuth sweeps -90 -> +90 deg, tilted down line by line.
Scan horizontalFans(int fans, int points_per_fan) {
  Scan scan;
  for (int f = 0; f < fans; ++f) {
    const double tilt = (20.0 - f * 0.5) * kDeg;
    for (int k = 0; k < points_per_fan; ++k) {
      const double azimuth = (-90.0 + 180.0 * k / (points_per_fan - 1)) * kDeg;
      scan.points.push_back({float(5.0 * std::cos(tilt) * std::cos(azimuth)),
                             float(5.0 * std::cos(tilt) * std::sin(azimuth)),
                             float(5.0 * std::sin(tilt))});
      scan.status.push_back(PointStatus::kValid);
    }
  }
  return scan;
}

TEST(ScanLines, SplitsVerticalFansWhereElevationJumpsBack) {
  Scan scan = verticalFans(40, 150);
  reconstructScanLines(scan, 20 * kDeg);
  ASSERT_EQ(scan.lines.size(), 40u);
  for (const ScanLine& line : scan.lines)
    EXPECT_EQ(line.count, 150u);
}

TEST(ScanLines, SplitsHorizontalFansWhereAzimuthJumpsBack) {
  Scan scan = horizontalFans(30, 181);
  reconstructScanLines(scan, 20 * kDeg);
  ASSERT_EQ(scan.lines.size(), 30u);
  EXPECT_TRUE(scan.isOrganised());
}

TEST(ScanLines, NoReturnsStayInsideTheLineStructure) {
  Scan scan = verticalFans(10, 100);
  // The last 5 beams of every fan saw nothing: NaN, as an organised file keeps them.
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (i % 100 >= 95) {
      scan.points[i] = {std::numeric_limits<float>::quiet_NaN(), 0, 0};
      scan.status[i] = PointStatus::kNoReturn;
    }
  }
  reconstructScanLines(scan, 20 * kDeg);
  ASSERT_EQ(scan.lines.size(), 10u);
  std::size_t covered = 0;
  for (const ScanLine& line : scan.lines)
    covered += line.count;
  EXPECT_EQ(covered, scan.size());
}

TEST(ScanLines, GapsForwardAlongTheLineDoNotSplitIt) {
  Scan scan = verticalFans(5, 160);
  // Drop a 40-degree band of sky in every fan: the sweep jumps forward, not back.
  Scan gappy;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (i % 160 >= 40 && i % 160 < 80) continue;
    gappy.points.push_back(scan.points[i]);
    gappy.status.push_back(PointStatus::kValid);
  }
  reconstructScanLines(gappy, 20 * kDeg);
  EXPECT_EQ(gappy.lines.size(), 5u);
}

TEST(ScanLines, ACloudWithoutSweepIsOneLine) {
  Scan scan;
  for (int i = 0; i < 10; ++i) {
    scan.points.push_back({1, 1, 1});
    scan.status.push_back(PointStatus::kValid);
  }
  reconstructScanLines(scan, 20 * kDeg);
  ASSERT_EQ(scan.lines.size(), 1u);
  EXPECT_EQ(scan.lines[0].count, 10u);
}

TEST(ScanLines, SaturatedRangeIsMarkedOnlyWhenItCrowds) {
  Scan scan = verticalFans(10, 100);
  // Give every point its own range, as a real scene does.
  for (std::size_t i = 0; i < scan.size(); ++i) {
    Point3f& p = scan.points[i];
    const float scale = (2.0F + 0.01F * float(i)) / std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
    p = {p.x * scale, p.y * scale, p.z * scale};
  }
  EXPECT_EQ(markSaturatedRange(scan), 0u) << "a natural range spread is no saturation";
  for (std::size_t i = 0; i < 50; ++i) {
    const Point3f p = scan.points[i * 7];
    const float scale = 32.77F / std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
    scan.points[i * 7] = {p.x * scale, p.y * scale, p.z * scale};
  }
  EXPECT_EQ(markSaturatedRange(scan), 50u);
  EXPECT_EQ(scan.status[7], PointStatus::kMaxRange);
}

}  // namespace
}  // namespace clearway
