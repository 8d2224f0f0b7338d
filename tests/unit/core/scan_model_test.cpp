#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "clearway/scan.h"

namespace clearway {
namespace {

Scan twoLines() {
  Scan scan;
  scan.points = {{1, 0, 0}, {2, 0, 0}, {0.1F, 0, 0}, {0, 3, 0}, {0, 4, 0}, {0, 5, 0}};
  scan.status.assign(6, PointStatus::kValid);
  scan.lines = {{0, 3}, {3, 3}};
  return scan;
}

TEST(ScanModel, OrganisedWhenEveryLineHasTheSameLength) {
  Scan scan = twoLines();
  EXPECT_TRUE(scan.isOrganised());
  EXPECT_EQ(scan.pointsPerLine(), 3u);
  scan.lines = {{0, 2}, {2, 4}};
  EXPECT_FALSE(scan.isOrganised());
  EXPECT_EQ(scan.pointsPerLine(), 4u);
}

TEST(ScanModel, SelfHitsAreMarkedNotDropped) {
  Scan scan = twoLines();
  EXPECT_EQ(markSelfHits(scan, 0.3), 1u);
  EXPECT_EQ(scan.size(), 6u);
  EXPECT_EQ(scan.status[2], PointStatus::kSelfHit);
  EXPECT_EQ(scan.validCount(), 5u);
}

TEST(ScanModel, BoundsIgnoreInvalidPoints) {
  Scan scan = twoLines();
  scan.points[5] = {100, 100, 100};
  scan.status[5] = PointStatus::kMaxRange;
  const Bounds bounds = validBounds(scan);
  EXPECT_FLOAT_EQ(bounds.max.y, 4.0F);
  EXPECT_FLOAT_EQ(bounds.min.x, 0.0F);
}

TEST(ScanModel, InvariantsCatchLinesThatDoNotCoverThePoints) {
  Scan scan = twoLines();
  EXPECT_NO_THROW(checkScanInvariants(scan));
  scan.lines = {{0, 3}, {3, 2}};
  EXPECT_THROW(checkScanInvariants(scan), std::logic_error);
}

TEST(ScanModel, InvariantsCatchAValidPointThatIsNaN) {
  Scan scan = twoLines();
  scan.points[1].x = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(checkScanInvariants(scan), std::logic_error);
  scan.status[1] = PointStatus::kNoReturn;
  EXPECT_NO_THROW(checkScanInvariants(scan));
}

}  // namespace
}  // namespace clearway
