// Multi-beam frames: rings from a PCD `ring` field, from the azimuth wrap (KITTI's order), and
// from the elevation angles when the frame's order tells nothing (--rings N).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "clearway/io/scan_io.h"
#include "clearway/io/scan_lines.h"
#include "clearway/pipeline.h"
#include "clearway/scan_summary.h"
#include "clearway/sensor_geometry.h"
#include "test_support.h"

namespace clearway {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr int kRings = 4;
constexpr int kPerRing = 360;

// Ring r at elevation -10 + 5 r deg, one return per degree of azimuth from 0 on, 10 m away.
Point3f ringPoint(int ring, int k) {
  const double elevation = (-10.0 + 5.0 * ring) * kDeg, azimuth = (k + 0.5) * kDeg;
  return {float(10.0 * std::cos(elevation) * std::cos(azimuth)),
          float(10.0 * std::cos(elevation) * std::sin(azimuth)), float(10.0 * std::sin(elevation))};
}

TEST(Rings, KittiOrderEndsARingWhereTheAzimuthHasGoneOnceAround) {
  Scan scan;
  for (int r = 0; r < kRings; ++r)
    for (int k = 0; k < kPerRing; ++k) {
      scan.points.push_back(ringPoint(r, k));
      scan.status.push_back(PointStatus::kValid);
    }
  reconstructScanLines(scan, 20.0 * kDeg);
  ASSERT_EQ(scan.lines.size(), std::size_t(kRings));
  for (const ScanLine& line : scan.lines)
    EXPECT_EQ(line.count, std::size_t(kPerRing));
  const SensorGeometry sensor = describeSensor(scan);
  EXPECT_EQ(sensor.kind, SensorKind::kMultiBeam);
  EXPECT_NEAR(sensor.between_line_step, 5.0 * kDeg, 0.1 * kDeg);
}

TEST(Rings, ShuffledFrameGetsItsRingsBackFromTheElevation) {
  Scan scan;
  for (int r = 0; r < kRings; ++r)
    for (int k = 0; k < kPerRing; ++k) {
      scan.points.push_back(ringPoint(r, k));
      scan.status.push_back(PointStatus::kValid);
    }
  std::mt19937 random(3);
  std::shuffle(scan.points.begin(), scan.points.end(), random);
  ASSERT_EQ(recoverRings(scan, kRings), "");
  ASSERT_EQ(scan.lines.size(), std::size_t(kRings));
  for (std::size_t l = 0; l < scan.lines.size(); ++l) {
    EXPECT_EQ(scan.lines[l].count, std::size_t(kPerRing));
    // Every point of a ring at that ring's elevation, in azimuth order.
    for (std::size_t i = scan.lines[l].first + 1; i < scan.lines[l].first + scan.lines[l].count;
         ++i) {
      const Point3f& p = scan.points[i];
      EXPECT_NEAR(std::asin(p.z / 10.0) / kDeg, -10.0 + 5.0 * double(l), 1e-3);
      const Point3f& q = scan.points[i - 1];
      EXPECT_LT(std::atan2(q.y, q.x), std::atan2(p.y, p.x));
    }
  }
}

// Rings that overlap in elevation (a head's lasers sit apart, so seen from one point each ring
// spreads over more than the step between rings) and a few stray returns far above and below:
// the widest gaps fall among the strays, one band takes nearly every return. Refused, with the
// reason, and the scan left as it was.
TEST(Rings, ARecoveryThatPutsMostReturnsInOneRingIsRefused) {
  Scan scan;
  std::mt19937 random(5);
  std::uniform_real_distribution<double> spread(-1.5, 1.5);  // [deg], against 1 deg between rings
  constexpr int kOverlapping = 8;
  for (int r = 0; r < kOverlapping; ++r)
    for (int k = 0; k < kPerRing; ++k) {
      const double elevation = (-10.0 + r + spread(random)) * kDeg, azimuth = (k + 0.5) * kDeg;
      scan.points.push_back({float(10.0 * std::cos(elevation) * std::cos(azimuth)),
                             float(10.0 * std::cos(elevation) * std::sin(azimuth)),
                             float(10.0 * std::sin(elevation))});
      scan.status.push_back(PointStatus::kValid);
    }
  for (const double stray : {-60.0, -45.0, -30.0, 30.0, 45.0, 60.0, 75.0}) {
    scan.points.push_back({float(std::cos(stray * kDeg)), 0.0F, float(std::sin(stray * kDeg))});
    scan.status.push_back(PointStatus::kValid);
  }
  scan.lines = {{0, scan.size()}};
  const std::vector<Point3f> before = scan.points;
  const std::string why_not = recoverRings(scan, kOverlapping);
  EXPECT_NE(why_not.find("do not fall into 8 rings"), std::string::npos) << why_not;
  ASSERT_EQ(scan.lines.size(), 1U);
  for (std::size_t i = 0; i < before.size(); ++i)
    EXPECT_EQ(scan.points[i].z, before[i].z) << i;
}

// A frame of kRings rings of kPerRing returns, one line per ring, lowest first.
void expectOneLinePerRing(const Scan& scan) {
  ASSERT_EQ(scan.lines.size(), std::size_t(kRings));
  for (std::size_t l = 0; l < scan.lines.size(); ++l) {
    EXPECT_EQ(scan.lines[l].count, std::size_t(kPerRing));
    const Point3f& p = scan.points[scan.lines[l].first];
    EXPECT_NEAR(std::asin(p.z / 10.0) / kDeg, -10.0 + 5.0 * double(l), 1e-2);
  }
  EXPECT_EQ(describeSensor(scan).kind, SensorKind::kMultiBeam);
}

// Text rows "x y z<between>ring", interleaved as a driver writes them: one return of every ring
// per firing.
std::string firingOrderRows(const char* between) {
  std::ostringstream rows;
  for (int k = 0; k < kPerRing; ++k)
    for (int r = 0; r < kRings; ++r) {
      const Point3f p = ringPoint(r, k);
      rows << p.x << ' ' << p.y << ' ' << p.z << between << r << '\n';
    }
  return rows.str();
}

TEST(Rings, APcdRingFieldMakesOneLinePerRing) {
  test::TemporaryDirectory directory;
  std::ostringstream pcd;
  const int points = kRings * kPerRing;
  pcd << "VERSION 0.7\nFIELDS x y z ring\nSIZE 4 4 4 2\nTYPE F F F U\nCOUNT 1 1 1 1\nWIDTH "
      << points << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << points << "\nDATA ascii\n";
  pcd << firingOrderRows(" ");
  const auto file = directory / "rings.pcd";
  test::writeBytes(file, pcd.str());
  expectOneLinePerRing(loadScan(file));
}

TEST(Rings, APlyLaserIdPropertyMakesOneLinePerRing) {
  test::TemporaryDirectory directory;
  std::ostringstream ply;
  const int points = kRings * kPerRing;
  // As VeloView exports a frame: firing after firing, each return tagged with its laser.
  ply << "ply\nformat ascii 1.0\nelement vertex " << points
      << "\nproperty float x\nproperty float y\nproperty float z\nproperty float intensity\n"
         "property ushort laser_id\nend_header\n";
  ply << firingOrderRows(" 7 ");  // intensity 7
  const auto file = directory / "rings.ply";
  test::writeBytes(file, ply.str());
  expectOneLinePerRing(loadScan(file));
}

// A ring field that holds no ring numbers is a corrupt file, not a frame of thousands of rings.
TEST(Rings, ARingFieldWithoutRingNumbersIsRefusedWithTheReason) {
  test::TemporaryDirectory directory;
  for (const char* bad : {"nan", "-1", "2.5", "70000"}) {
    std::ostringstream pcd;
    pcd << "VERSION 0.7\nFIELDS x y z ring\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\n"
           "WIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n"
           "1 0 0 0\n0 1 0 1\n1 1 0 "
        << bad << "\n";
    const auto file = directory / "bad_ring.pcd";
    test::writeBytes(file, pcd.str());
    try {
      loadScan(file);
      ADD_FAILURE() << "ring " << bad << " was accepted";
    } catch (const ScanError& error) {
      EXPECT_NE(std::string(error.what()).find("ring number"), std::string::npos) << error.what();
    }
  }
}

// Firing after firing, one return of each ring per degree of azimuth in the order 2, 0, 3, 1
// (interleaved, as a VLP-16 fires), a few returns of the top ring missing (sky): the columns
// become rings again, each in azimuth order.
TEST(Rings, AFrameInFiringOrderGetsItsRingsBackFromItsElevationBands) {
  Scan scan;
  std::size_t missing = 0;
  for (int k = 0; k < kPerRing; ++k)
    for (const int r : {2, 0, 3, 1}) {
      if (r == 3 && k % 7 == 0) {
        ++missing;
        continue;
      }
      scan.points.push_back(ringPoint(r, k));
      scan.status.push_back(PointStatus::kValid);
    }
  reconstructScanLines(scan, 20.0 * kDeg);
  ASSERT_NE(scan.lines.size(), std::size_t(kRings));  // no rings, before
  EXPECT_EQ(recoverFiringOrderRings(scan), std::size_t(kRings));
  ASSERT_EQ(scan.lines.size(), std::size_t(kRings));
  for (std::size_t l = 0; l < scan.lines.size(); ++l) {
    EXPECT_EQ(scan.lines[l].count, std::size_t(kPerRing) - (l == 3 ? missing : 0));
    for (std::size_t i = scan.lines[l].first; i < scan.lines[l].first + scan.lines[l].count; ++i)
      EXPECT_NEAR(std::asin(scan.points[i].z / 10.0) / kDeg, -10.0 + 5.0 * double(l), 1e-3);
  }
  EXPECT_EQ(describeSensor(scan).kind, SensorKind::kMultiBeam);
}

// Firing after firing, eight lasers 1 deg apart whose returns each spread 1.5 deg either way in
// elevation seen from one point (lasers that sit apart on the head, as an HDL-64E's): no bands
// separate them. The frame is left as the line reconstruction read it, and says why in
// ScanMetadata::caution, which the result's reason leads with.
TEST(Rings, AFiringOrderFrameWhoseRingsOverlapSaysSo) {
  Scan scan;
  std::mt19937 random(5);
  std::uniform_real_distribution<double> spread(-1.5, 1.5);
  for (int k = 0; k < kPerRing; ++k)
    for (const int r : {5, 1, 6, 2, 7, 3, 4, 0}) {
      const double elevation = (-10.0 + r + spread(random)) * kDeg, azimuth = (k + 0.5) * kDeg;
      scan.points.push_back({float(10.0 * std::cos(elevation) * std::cos(azimuth)),
                             float(10.0 * std::cos(elevation) * std::sin(azimuth)),
                             float(10.0 * std::sin(elevation))});
      scan.status.push_back(PointStatus::kValid);
    }
  reconstructScanLines(scan, 20.0 * kDeg);
  const std::size_t lines = scan.lines.size();
  EXPECT_EQ(recoverFiringOrderRings(scan), 0U);
  EXPECT_EQ(scan.lines.size(), lines);
  EXPECT_NE(scan.metadata.caution.find("multi-beam frame kept firing after firing"),
            std::string::npos)
      << scan.metadata.caution;
  EXPECT_NE(toText(summarise(scan)).find("caution:"), std::string::npos);
  // Nothing is green on such a frame, and the reason starts with the caution, not with advice
  // for a scan it is not ("scan with more lines").
  const PipelineResult result = runPipeline(scan, SegmentationParams{});
  EXPECT_FALSE(result.trusted() && result.map.counts[std::size_t(CellLabel::kTraversable)] > 0);
  EXPECT_EQ(result.reason.rfind(scan.metadata.caution, 0), 0U) << result.reason;
}

// A 2D scanner's vertical fans (100 deg at 1 deg, the LMS200's narrow mode) turned about the
// vertical: short lines too, at fixed elevations too, but over a field of view no multi-beam head
// has. They stay fans.
TEST(Rings, ARotatingScannersFansAreNotTakenForFirings) {
  Scan scan;
  for (int line = 0; line < 180; ++line)
    for (int k = 0; k <= 100; ++k) {
      const double elevation = (-50.0 + k) * kDeg, azimuth = 2.0 * line * kDeg;
      scan.points.push_back({float(5.0 * std::cos(elevation) * std::cos(azimuth)),
                             float(5.0 * std::cos(elevation) * std::sin(azimuth)),
                             float(5.0 * std::sin(elevation))});
      scan.status.push_back(PointStatus::kValid);
    }
  reconstructScanLines(scan, 20.0 * kDeg);
  ASSERT_EQ(scan.lines.size(), 180U);
  EXPECT_EQ(recoverFiringOrderRings(scan), 0U);
  EXPECT_EQ(scan.lines.size(), 180U);
  EXPECT_TRUE(scan.metadata.caution.empty()) << scan.metadata.caution;
}

}  // namespace
}  // namespace clearway
