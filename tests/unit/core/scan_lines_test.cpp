#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "clearway/io/scan_lines.h"
#include "synthetic_fans.h"

namespace clearway {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

using test::horizontalFans;
using test::verticalFans;

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
