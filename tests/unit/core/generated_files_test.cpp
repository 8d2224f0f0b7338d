// Every format, written by the test with known content, read back through loadScan().

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <sstream>

#include "clearway/io/scan_io.h"
#include "test_support.h"

namespace clearway {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// A RoSi-shaped scan of a 4 m sphere: half lines of 180 points, alpha 0..89.5 deg, every 7th
// beam a no-return.
Scan rosiSphere(int lines) {
  Scan scan;
  for (int l = 0; l < lines; ++l) {
    const double beta = 2.0 * std::numbers::pi * l / lines;
    scan.lines.push_back({scan.size(), 180, beta});
    for (int k = 0; k < 180; ++k) {
      const double alpha = 0.5 * k * kDeg;
      const double d = 4.0;
      const bool no_return = (l * 180 + k) % 7 == 3;
      const float nan = std::numeric_limits<float>::quiet_NaN();
      scan.points.push_back(no_return ? Point3f{nan, nan, nan}
                                      : Point3f{float(std::cos(beta) * std::cos(alpha) * d),
                                                float(std::sin(beta) * std::cos(alpha) * d),
                                                float(std::sin(alpha) * d)});
      scan.status.push_back(no_return ? PointStatus::kNoReturn : PointStatus::kValid);
      scan.intensity.push_back(float(k));
      scan.alpha.push_back(float(alpha));
    }
  }
  return scan;
}

class RosiPcdRoundTrip : public ::testing::TestWithParam<PcdEncoding> {};

TEST_P(RosiPcdRoundTrip, KeepsLinesAnglesIntensityAndNoReturns) {
  test::TemporaryDirectory directory;
  const Scan written = rosiSphere(12);
  const auto file = directory / "scan.pcd";
  saveRosiPcd(written, file, GetParam());
  const Scan read = loadScan(file);

  ASSERT_EQ(read.size(), written.size());
  ASSERT_EQ(read.lines.size(), 12u);
  EXPECT_TRUE(read.isOrganised());
  EXPECT_EQ(read.pointsPerLine(), 180u);
  EXPECT_EQ(read.validCount(), written.validCount());
  ASSERT_EQ(read.intensity.size(), read.size());
  ASSERT_EQ(read.alpha.size(), read.size());
  for (std::size_t l = 0; l < 12; ++l)
    EXPECT_NEAR(read.lines[l].beta, written.lines[l].beta, 1e-6);
  for (std::size_t i = 0; i < read.size(); ++i) {
    ASSERT_EQ(read.status[i], written.status[i]) << "point " << i;
    EXPECT_FLOAT_EQ(read.intensity[i], written.intensity[i]);
    if (!read.isValid(i)) continue;
    EXPECT_NEAR(read.points[i].x, written.points[i].x, 1e-5);
    EXPECT_NEAR(read.points[i].z, written.points[i].z, 1e-5);
  }
}

INSTANTIATE_TEST_SUITE_P(Encodings, RosiPcdRoundTrip,
                         ::testing::Values(PcdEncoding::kAscii, PcdEncoding::kBinary,
                                           PcdEncoding::kBinaryCompressed));

TEST(RosiPcd, SavingReplacesTheFileAtomicallyAndLeavesNoTemporaries) {
  test::TemporaryDirectory directory;
  const auto file = directory / "scan.pcd";
  saveRosiPcd(rosiSphere(4), file);
  saveRosiPcd(rosiSphere(6), file);
  EXPECT_EQ(loadScan(file).lines.size(), 6u);
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(directory.path()))
    ++entries;
  EXPECT_EQ(entries, 1u);
}

TEST(RosiPcd, SensorPoseSurvivesTheViewpoint) {
  test::TemporaryDirectory directory;
  Scan scan = rosiSphere(4);
  SensorPose pose;
  pose.position = {1.0, 2.0, 0.5};
  // 90 degrees about z
  pose.rotation = {0, -1, 0, 1, 0, 0, 0, 0, 1};
  scan.sensor_pose = pose;
  saveRosiPcd(scan, directory / "posed.pcd");
  const Scan read = loadScan(directory / "posed.pcd");
  ASSERT_TRUE(read.sensor_pose.has_value());
  EXPECT_NEAR(read.sensor_pose->position[1], 2.0, 1e-6);
  EXPECT_NEAR(read.sensor_pose->rotation[1], -1.0, 1e-6);
  EXPECT_NEAR(read.sensor_pose->rotation[3], 1.0, 1e-6);
}

TEST(GeneratedFiles, UnorganisedPcdGetsItsLinesReconstructed) {
  test::TemporaryDirectory directory;
  Scan scan = rosiSphere(10);
  // Drop the no-returns and the line structure, as the PCL room scan does.
  Scan flat;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!scan.isValid(i)) continue;
    flat.points.push_back(scan.points[i]);
    flat.status.push_back(PointStatus::kValid);
  }
  flat.lines = {{0, flat.size()}};
  saveRosiPcd(flat, directory / "flat.pcd");
  const Scan read = loadScan(directory / "flat.pcd");
  EXPECT_EQ(read.lines.size(), 10u);
  EXPECT_EQ(read.size(), flat.size());
}

TEST(GeneratedFiles, XyzWithIntensityCommentsAndAHeader) {
  test::TemporaryDirectory directory;
  std::ostringstream text;
  text << "x y z intensity\n# a comment\n";
  for (int k = 0; k < 90; ++k) {
    const double a = k * kDeg;
    text << 2 * std::cos(a) << ' ' << 2 * std::sin(a) << " 0.5 " << k << "\n";
  }
  test::writeBytes(directory / "cloud.xyz", text.str());
  const Scan scan = loadScan(directory / "cloud.xyz");
  ASSERT_EQ(scan.size(), 90u);
  ASSERT_EQ(scan.intensity.size(), 90u);
  EXPECT_FLOAT_EQ(scan.intensity[42], 42.0F);
  EXPECT_NEAR(scan.points[0].x, 2.0, 1e-6);
}

TEST(GeneratedFiles, KittiBinaryRecords) {
  test::TemporaryDirectory directory;
  std::string bytes;
  for (int k = 0; k < 64; ++k) {
    const float record[4] = {float(5 + k), -1.0F, 0.25F, 0.5F};
    bytes.append(reinterpret_cast<const char*>(record), sizeof record);
  }
  test::writeBytes(directory / "000000.bin", bytes);
  const Scan scan = loadScan(directory / "000000.bin");
  ASSERT_EQ(scan.size(), 64u);
  EXPECT_FLOAT_EQ(scan.points[3].x, 8.0F);
  EXPECT_FLOAT_EQ(scan.intensity[3], 0.5F);
}

std::string plyHeader(const std::string& format, int vertices) {
  return "ply\nformat " + format + " 1.0\ncomment made by a test\nelement vertex " +
         std::to_string(vertices) +
         "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar intensity\n"
         "element face 0\nproperty list uchar int vertex_indices\nend_header\n";
}

TEST(GeneratedFiles, PlyAsciiAndBothBinaryByteOrders) {
  test::TemporaryDirectory directory;
  std::string ascii = plyHeader("ascii", 3) + "1 2 3 10\n4 5 6 20\n7 8 9 30\n";
  test::writeBytes(directory / "a.ply", ascii);

  auto binary = [](bool big_endian) {
    std::string bytes = plyHeader(big_endian ? "binary_big_endian" : "binary_little_endian", 3);
    for (int v = 0; v < 3; ++v) {
      for (int c = 0; c < 3; ++c) {
        const float value = float(3 * v + c + 1);
        char raw[4];
        std::memcpy(raw, &value, 4);
        if (big_endian) std::swap(raw[0], raw[3]), std::swap(raw[1], raw[2]);
        bytes.append(raw, 4);
      }
      bytes.push_back(char(10 * (v + 1)));
    }
    return bytes;
  };
  test::writeBytes(directory / "le.ply", binary(false));
  test::writeBytes(directory / "be.ply", binary(true));

  for (const char* name : {"a.ply", "le.ply", "be.ply"}) {
    SCOPED_TRACE(name);
    LoadOptions options;
    options.self_hit_radius = 0.0;
    const Scan scan = loadScan(directory / name, options);
    ASSERT_EQ(scan.size(), 3u);
    EXPECT_FLOAT_EQ(scan.points[1].x, 4.0F);
    EXPECT_FLOAT_EQ(scan.points[2].z, 9.0F);
    EXPECT_FLOAT_EQ(scan.intensity[2], 30.0F);
  }
}

TEST(GeneratedFiles, UosConvertsCentimetresAndAxesAndReadsThePose) {
  test::TemporaryDirectory directory;
  // 3DTK: x sideways, y up, z forward, centimetres.
  test::writeBytes(directory / "scan001.3d", "100 50 300\n-20 10 400\n");
  test::writeBytes(directory / "scan001.pose", "100 0 200\n0 90 0\n");
  const Scan scan = loadScan(directory / "scan001.3d");
  ASSERT_EQ(scan.size(), 2u);
  EXPECT_NEAR(scan.points[0].x, 3.0, 1e-6);   // forward = z / 100
  EXPECT_NEAR(scan.points[0].y, -1.0, 1e-6);  // left = -x / 100
  EXPECT_NEAR(scan.points[0].z, 0.5, 1e-6);   // up = y / 100
  ASSERT_TRUE(scan.sensor_pose);
  EXPECT_NEAR(scan.sensor_pose->position[0], 2.0, 1e-9);
  EXPECT_NEAR(scan.sensor_pose->position[1], -1.0, 1e-9);
  // 90 degrees about 3DTK's up axis is a rotation about our z axis: a proper rotation whose
  // z row and column are untouched.
  const auto& r = scan.sensor_pose->rotation;
  EXPECT_NEAR(r[8], 1.0, 1e-9);
  EXPECT_NEAR(r[0], 0.0, 1e-9);
  EXPECT_NEAR(std::abs(r[1]), 1.0, 1e-9);
  const double determinant = r[0] * (r[4] * r[8] - r[5] * r[7]) -
                             r[1] * (r[3] * r[8] - r[5] * r[6]) +
                             r[2] * (r[3] * r[7] - r[4] * r[6]);
  EXPECT_NEAR(determinant, 1.0, 1e-9);
}

}  // namespace
}  // namespace clearway
