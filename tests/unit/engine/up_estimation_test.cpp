// Scans without a pose: turned about a horizontal axis and stripped of their pose, each result is
// either the right floor (normal within 5 deg of the truth, reported as estimated) or no ground
// with the reason - never a wrong floor (issue: "Without a pose a wall can become the floor").

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <numbers>

#include "clearway/io/scan_io.h"
#include "clearway/pipeline.h"
#include "clearway/sim/builtin_scenes.h"
#include "clearway/sim/rosi_simulator.h"
#include "test_support.h"

namespace clearway {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
const double kTurns[] = {0.0, 30.0, 60.0, 90.0, 135.0, 180.0};

Eigen::Matrix3d worldRotation(const Scan& scan) {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  if (scan.sensor_pose)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        rotation(r, c) = scan.sensor_pose->rotation[std::size_t(3 * r + c)];
  return rotation;
}

// The scan turned by `degrees` about the world's x axis around the scanner, without its pose;
// `true_up` is the world's up in the turned frame.
Scan turnedWithoutPose(const Scan& scan, double degrees, Eigen::Vector3d& true_up) {
  const Eigen::Matrix3d turn(Eigen::AngleAxisd(degrees * kDeg, Eigen::Vector3d::UnitX()));
  const Eigen::Matrix3d transform = turn * worldRotation(scan);
  Scan turned = scan;
  for (Point3f& p : turned.points) {
    const Eigen::Vector3d q = transform * Eigen::Vector3d(p.x, p.y, p.z);
    p = {float(q.x()), float(q.y()), float(q.z())};
  }
  turned.sensor_pose.reset();
  turned.pose_source = PoseSource::kNone;
  true_up = turn * Eigen::Vector3d::UnitZ();
  return turned;
}

enum class Outcome { kRightFloor, kRefused, kWrongFloor };

struct Case {
  std::string name;
  double turn = 0.0;
  Outcome outcome = Outcome::kRefused;
  double error_deg = 0.0;
  double confidence = 0.0;
  std::string reason;
};

Case judge(const std::string& name, const Scan& scan, double degrees) {
  Eigen::Vector3d true_up;
  const Scan turned = turnedWithoutPose(scan, degrees, true_up);
  const ScanAnalysis analysis = analyseScan(turned, SegmentationParams{});
  Case result;
  result.name = name;
  result.turn = degrees;
  result.confidence = analysis.up_confidence;
  if (!analysis.ground_found) {
    result.outcome = Outcome::kRefused;
    result.reason = analysis.reason;
    return result;
  }
  const Plane& floor = analysis.planes.planes[std::size_t(analysis.reference_ground)];
  const double cosine = std::abs(floor.normal.dot(true_up));
  result.error_deg = std::acos(std::min(1.0, cosine)) / kDeg;
  const bool up_side = analysis.up.dot(true_up) > 0;
  result.outcome = result.error_deg <= 5.0 && up_side ? Outcome::kRightFloor : Outcome::kWrongFloor;
  return result;
}

void expectNeverWrong(const std::vector<Case>& cases) {
  for (const Case& c : cases) {
    std::cout << std::left << std::setw(28) << c.name << std::fixed << std::setprecision(0)
              << std::setw(5) << c.turn << " deg  "
              << (c.outcome == Outcome::kRightFloor ? "right floor"
                  : c.outcome == Outcome::kRefused  ? "refused"
                                                    : "WRONG FLOOR")
              << "  error " << std::setprecision(1) << c.error_deg << " deg  confidence "
              << std::setprecision(2) << c.confidence << "\n";
    EXPECT_NE(c.outcome, Outcome::kWrongFloor) << c.name << " turned " << c.turn << " deg";
    if (c.outcome == Outcome::kRefused) {
      EXPECT_NE(c.reason.find("no pose"), std::string::npos) << c.name << ": " << c.reason;
    }
  }
}

std::vector<Case> allTurns(const std::string& name, const Scan& scan) {
  std::vector<Case> cases;
  for (double degrees : kTurns)
    cases.push_back(judge(name, scan, degrees));
  return cases;
}

class SimulatedScenesWithoutPose : public ::testing::TestWithParam<std::string> {};

TEST_P(SimulatedScenesWithoutPose, NeverAWrongFloor) {
  const sim::Scene scene = *sim::builtinScene(GetParam());
  sim::SensorModel sensor;
  sensor.lines = 200;
  const sim::SimulatedScan simulated =
      sim::simulateRosi(scene, sensor, sim::defaultPlacement(scene));
  const std::vector<Case> cases = allTurns(GetParam(), simulated.scan);
  expectNeverWrong(cases);
}

INSTANTIATE_TEST_SUITE_P(Scenes, SimulatedScenesWithoutPose,
                         ::testing::ValuesIn(sim::builtinSceneNames()));

class RealScansWithoutPose : public ::testing::TestWithParam<std::string> {};

TEST_P(RealScansWithoutPose, NeverAWrongFloor) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, GetParam());
  const Scan scan = loadScan(file);
  const std::vector<Case> cases = allTurns(GetParam(), scan);
  expectNeverWrong(cases);
}

INSTANTIATE_TEST_SUITE_P(Real, RealScansWithoutPose,
                         ::testing::Values("pcl-room/room_scan1.pcd", "octomap-stairs/scan.dat",
                                           "3dtk/scan000.3d", "hannover1/scan100.3d",
                                           "hannover1/scan440.3d", "kitti/000001.bin",
                                           "kitti/000002.bin"));

}  // namespace
}  // namespace clearway
