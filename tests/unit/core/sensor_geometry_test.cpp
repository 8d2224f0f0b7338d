// The sensor's geometry read from the scan: which lines lie side by side when the file gives no
// turntable angle.

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <numbers>

#include "clearway/scan.h"
#include "clearway/sensor_geometry.h"
#include "synthetic_fans.h"

namespace clearway {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(SensorGeometry, ANoddingScannersFansAreOrderedByTheirTilt) {
  constexpr int kFans = 200;
  Scan scan = test::noddingFans(kFans, 0.5);
  test::oneLinePer(scan, 181);
  const SensorGeometry sensor = describeSensor(scan);
  EXPECT_EQ(sensor.kind, SensorKind::kRotating2D);
  EXPECT_NEAR(sensor.between_line_step, 0.5 * kDeg, 0.02 * kDeg);
  EXPECT_NEAR(sensor.along_line_step, 1.0 * kDeg, 0.02 * kDeg);
  EXPECT_FALSE(sensor.closed_turn);
  // Side by side in the file's order: the angles step the same way, by the tilt's step.
  ASSERT_EQ(sensor.line_angle.size(), std::size_t(kFans));
  const double way = sensor.line_angle[1] > sensor.line_angle[0] ? 1.0 : -1.0;
  for (int f = 1; f < kFans; ++f)
    EXPECT_NEAR(way * std::remainder(
                          sensor.line_angle[std::size_t(f)] - sensor.line_angle[std::size_t(f - 1)],
                          2.0 * std::numbers::pi),
                0.5 * kDeg, 0.02 * kDeg)
        << f;
}

// A turntable turning about the vertical (a RoSi's vertical fans): the direction of each fan's
// points about z, as before.
TEST(SensorGeometry, VerticalFansKeepTheirDirectionAboutTheVertical) {
  constexpr int kFans = 180;
  Scan scan = test::verticalFans(kFans, 150);
  test::oneLinePer(scan, 150);
  const SensorGeometry sensor = describeSensor(scan);
  EXPECT_EQ(sensor.kind, SensorKind::kRotating2D);
  EXPECT_NEAR(sensor.between_line_step, 2.0 * kDeg, 0.01 * kDeg);
  EXPECT_TRUE(sensor.closed_turn);
  for (int f = 0; f < kFans; ++f)
    EXPECT_NEAR(
        std::remainder(sensor.line_angle[std::size_t(f)] - f * 2.0 * kDeg, 2.0 * std::numbers::pi),
        0.0, 1e-3)
        << f;
}

// A dense RoSi scan (thousands of fans, each with its turntable angle) is described from a sample
// of its usable fans: here every third fan is empty (no returns), and a sample of every third line
// regardless of use would have found no fan to measure.
TEST(SensorGeometry, ADenseScansFansAreMeasuredFromTheUsableOnes) {
  constexpr int kFans = 1800, kPerFan = 90;
  constexpr double kBetweenDeg = 360.0 / kFans, kAlongDeg = 160.0 / (kPerFan - 1);
  Scan scan;
  for (int f = 0; f < kFans; ++f) {
    const double azimuth = f * kBetweenDeg * kDeg;
    scan.lines.push_back({scan.points.size(), std::size_t(kPerFan), azimuth});
    for (int k = 0; k < kPerFan; ++k) {
      const double elevation = (80.0 - k * kAlongDeg) * kDeg;
      test::addDirection(scan,
                         {std::cos(elevation) * std::cos(azimuth),
                          std::cos(elevation) * std::sin(azimuth), std::sin(elevation)},
                         4.0);
      if (f % 3 == 0) scan.status.back() = PointStatus::kNoReturn;
    }
  }
  const SensorGeometry sensor = describeSensor(scan, 2);
  EXPECT_EQ(sensor.kind, SensorKind::kRotating2D);
  EXPECT_NEAR(sensor.along_line_step, kAlongDeg * kDeg, 1e-4 * kDeg);
  EXPECT_NEAR(sensor.between_line_step, kBetweenDeg * kDeg, 1e-4 * kDeg);
  EXPECT_TRUE(sensor.closed_turn);
  for (int f = 0; f < kFans; ++f)
    if (f % 3 == 0)
      EXPECT_TRUE(std::isnan(sensor.line_angle[std::size_t(f)])) << f;
    else
      EXPECT_DOUBLE_EQ(sensor.line_angle[std::size_t(f)], f * kBetweenDeg * kDeg) << f;
}

// The density check's hidden obstacle for fans about a tilted axis. With the axis along z the
// general geometry gives what a RoSi's vertical fans do.
TEST(SensorGeometry, HiddenObstacleAboutAnAxisAlongZIsTheVerticalFansOne) {
  SensorGeometry rosi;
  rosi.kind = SensorKind::kRotating2D;
  rosi.along_line_step = 0.5 * kDeg;
  rosi.between_line_step = 0.9 * kDeg;
  SensorGeometry about_z = rosi;
  about_z.tilted_axis = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  constexpr double kHeight = 1.2;
  for (const Eigen::Vector2d& at :
       {Eigen::Vector2d(2.0, 0.5), Eigen::Vector2d(-4.0, 3.0), Eigen::Vector2d(0.3, -7.5)}) {
    const Eigen::Vector3d ground(at.x(), at.y(), -kHeight);
    EXPECT_NEAR(hiddenObstacleSize(about_z, ground, up, kHeight),
                hiddenObstacleSize(rosi, ground, up, kHeight), 1e-9)
        << at.transpose();
  }
}

// A RoSi whose turntable axis points forward, level, 1.2 m up (the built-in scenes' placement):
// its lines turn about the forward axis, 3.6 deg apart (100 lines). Straight ahead and below, the
// next line's sample lies beside this one on the ground, 1.2 m x 3.6 deg away, as for an upright
// axis. 3 m to the side, the lines lie one above the other: the next line's beam passes 0.2 m
// over this line's sample (the distance from the axis x 3.6 deg), so an obstacle 0.2 m high can
// stand there unseen. It counts as an obstacle twice that wide, as a fan's own step does; counted
// sideways, 0.2 m, a 0.13 m box beside such a scanner was driven over (a helper's clutter scene).
TEST(SensorGeometry, HiddenObstacleBesideAForwardTurntableIsWhereItsLinesLieOneAboveTheOther) {
  SensorGeometry rosi;
  rosi.kind = SensorKind::kRotating2D;
  rosi.along_line_step = 0.5 * kDeg;
  rosi.between_line_step = 3.6 * kDeg;
  // The scanner's frame: z the turntable axis (forward), x up, y to the side.
  const Eigen::Vector3d up = Eigen::Vector3d::UnitX();
  constexpr double kHeight = 1.2;
  const Eigen::Vector3d ahead(-kHeight, 0.0, 4.0), beside(-kHeight, 3.0, 4.0);
  EXPECT_NEAR(hiddenObstacleSize(rosi, ahead, up, kHeight), kHeight * 3.6 * kDeg, 1e-3);
  // The neighbouring line's beam above the sample beside (turned about the axis by its step the
  // way that lifts it), followed to where it passes closest over the sample.
  const Eigen::Vector3d next =
      Eigen::AngleAxisd(-3.6 * kDeg, Eigen::Vector3d::UnitZ()) * beside.normalized();
  double clearance = 0.0, nearest = std::numeric_limits<double>::infinity();
  for (double t = 0.5 * beside.norm(); t <= 1.5 * beside.norm(); t += 1e-4) {
    const Eigen::Vector3d at = t * next;
    const double apart = (at - beside - (at - beside).dot(up) * up).norm();
    if (apart < nearest) nearest = apart, clearance = (at - beside).dot(up);
  }
  EXPECT_NEAR(clearance, 0.2, 0.01);
  EXPECT_NEAR(hiddenObstacleSize(rosi, beside, up, kHeight), 2.0 * clearance, 0.02);
  // With the axis upright the same turn moves the sample sideways only: as before.
  const Eigen::Vector3d upright_beside(3.0, 4.0, -kHeight);
  EXPECT_NEAR(hiddenObstacleSize(rosi, upright_beside, Eigen::Vector3d::UnitZ(), kHeight),
              5.0 * 3.6 * kDeg, 1e-9);
}

// A nodding scanner 0.5 m up, its fans about the sideways axis 0.2 deg apart, 1 deg between the
// beams of a fan: 5 m ahead, a fan's neighbouring beams are 5 m x 1 deg = 0.087 m apart sideways,
// and the next fan's sample lies 0.18 m farther out, of which the farther beam protects all but
// 2 x 5 m x 0.2 deg = 0.035 m. Read as vertical fans, the 1 deg step was taken for the one that
// moves the sample outwards (0.175 m), and the tilt's for the sideways one.
TEST(SensorGeometry, HiddenObstacleForANoddingScannerFollowsItsAxis) {
  SensorGeometry nodding;
  nodding.kind = SensorKind::kRotating2D;
  nodding.along_line_step = 1.0 * kDeg;
  nodding.between_line_step = 0.2 * kDeg;
  nodding.tilted_axis = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  constexpr double kHeight = 0.5;
  const Eigen::Vector3d ahead(5.0, 0.0, -kHeight);
  const double range = ahead.norm();
  EXPECT_NEAR(hiddenObstacleSize(nodding, ahead, up, kHeight), range * 1.0 * kDeg, 1e-3);
  // The spacing the triangles allow: the tilt's step stretched on the ground, the fan's across.
  EXPECT_NEAR(expectedGroundSpacing(nodding, 5.0, kHeight),
              (25.0 + kHeight * kHeight) / kHeight * 0.2 * kDeg, 1e-9);
}

}  // namespace
}  // namespace clearway
