// The step a long ground triangle of one plane may hide (EdgeLimit::spannedStep): behind a drop
// away from the scanner the ground lies in the drop's shadow, and the triangle bridging it from the
// edge to the first return beyond shows the drop as a gentle slope.

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cstdint>
#include <numbers>
#include <vector>

#include "../../../core/src/segmentation/ground_triangles.h"
#include "clearway/sensor_geometry.h"

namespace clearway {
namespace {

constexpr double kDegree = std::numbers::pi / 180;

// A RoSi's geometry: fans 0.72 deg apart (250 lines), 0.5 deg between returns.
SensorGeometry rosi() {
  SensorGeometry sensor;
  sensor.kind = SensorKind::kRotating2D;
  sensor.along_line_step = 0.5 * kDegree;
  sensor.between_line_step = 0.72 * kDegree;
  return sensor;
}

// The step spanned by the triangle of `corners` (map frame, the scanner above the origin at 1.2 m)
// on one horizontal ground plane at height 0.
double spannedStep(const std::vector<Eigen::Vector3f>& corners) {
  const SensorGeometry sensor = rosi();
  detail::EdgeLimit limit{corners, sensor};
  limit.scanner_height = 1.2;
  limit.plane_heights = {Eigen::Vector3d::Zero()};
  const std::vector<std::int32_t> ground_of(corners.size(), 0);
  return limit.spannedStep(ground_of, 0, 1, 2);
}

// At 4 m the fans' returns lie about 0.13 m apart along the beam: a triangle reaching 0.5 m
// bridged ground no beam saw.
TEST(SpannedStep, ALongTriangleDroppingAwayFromTheScannerSpansItsDrop) {
  EXPECT_NEAR(spannedStep({{4.0F, 0.0F, 0.0F}, {4.5F, 0.05F, -0.07F}, {4.5F, -0.05F, -0.07F}}),
              0.07, 1e-6);
}

TEST(SpannedStep, GroundRisingAwayFromTheScannerIsSeenOnItsSlope) {
  EXPECT_EQ(spannedStep({{4.0F, 0.0F, 0.0F}, {4.5F, 0.05F, 0.07F}, {4.5F, -0.05F, 0.07F}}), 0.0);
}

// A triangle only as long as the samples are apart bridges ground no beam saw either: its drop
// may be a step anywhere between them.
TEST(SpannedStep, ATriangleAsLongAsTheSamplesAreApartSpansItsDropToo) {
  EXPECT_NEAR(spannedStep({{4.0F, 0.0F, 0.0F}, {4.2F, 0.05F, -0.07F}, {4.2F, -0.05F, -0.07F}}),
              0.07, 1e-6);
}

// Shorter than the cells' step rule's run (kStepRunLength), the cells compare the heights.
TEST(SpannedStep, ATriangleShorterThanTheStepRulesRunSpansNothing) {
  EXPECT_EQ(spannedStep({{4.0F, 0.0F, 0.0F}, {4.1F, 0.05F, -0.07F}, {4.1F, -0.05F, -0.07F}}), 0.0);
}

TEST(SpannedStep, ThePlanesOwnSlopeIsNoStep) {
  const std::vector<Eigen::Vector3f> corners = {
      {4.0F, 0.0F, 0.0F}, {4.5F, 0.05F, -0.07F}, {4.5F, -0.05F, -0.07F}};
  const SensorGeometry sensor = rosi();
  detail::EdgeLimit limit{corners, sensor};
  limit.scanner_height = 1.2;
  limit.plane_heights = {Eigen::Vector3d(0.56, -0.14, 0.0)};  // falls 0.14 m per metre along x
  EXPECT_NEAR(limit.spannedStep({0, 0, 0}, 0, 1, 2), 0.0, 1e-6);
}

}  // namespace
}  // namespace clearway
