#include "clearway/hardware/pose_source.h"

#include <chrono>
#include <cmath>
#include <ctime>

#include "clearway/hardware/line_protocol.h"
#include "serial_port.h"

namespace clearway::hardware {
namespace {

bool finite(const RigidPose& pose) {
  return pose.translation.allFinite() && pose.rotation.coeffs().allFinite();
}

std::string nowIso8601() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  ::gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

}  // namespace

SensorPose sensorPoseOf(const RigidPose& world_from_scanner) {
  SensorPose pose;
  const auto& t = world_from_scanner.translation;
  pose.position = {t.x(), t.y(), t.z()};
  const Eigen::Matrix3d r = world_from_scanner.rotation.toRotationMatrix();
  for (int i = 0; i < 9; ++i)
    pose.rotation[std::size_t(i)] = r(i / 3, i % 3);  // row-major
  return pose;
}

PoseReading PoseSource::read(int timeout_ms) {
  PoseReading reading = doRead(timeout_ms);
  reading.time = nowIso8601();
  if (!reading.ok()) return reading;
  if (!finite(reading.world_from_scanner) ||
      std::abs(reading.world_from_scanner.rotation.norm() - 1.0) > 1e-6) {
    reading.error = description() + " gave an unusable pose (not finite or not a rotation)";
  }
  return reading;
}

PoseReading FixedMounting::doRead(int) {
  PoseReading reading;
  reading.world_from_scanner = mounting_;
  reading.source = "mounting";
  return reading;
}

std::string FixedMounting::doDescribe() const {
  return "the fixed mounting " + formatPose(mounting_);
}

ArmPoseSource::ArmPoseSource(std::string port, RigidPose tool_from_scanner)
    : port_(std::move(port)), tool_from_scanner_(tool_from_scanner) {}

std::string ArmPoseSource::doDescribe() const {
  return "the arm controller on " + port_;
}

PoseReading ArmPoseSource::doRead(int timeout_ms) {
  PoseReading reading;
  reading.source = "arm";
  detail::SerialPort port(port_);
  if (!port.error().empty()) {
    reading.error = port.error();
    return reading;
  }
  if (!port.send(arm::poseQuery())) {
    reading.error = "cannot write to the arm controller on " + port_;
    return reading;
  }
  line_protocol::LineSplitter lines;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (std::chrono::steady_clock::now() < deadline) {
    if (!detail::waitReadable(port.fd(), 20)) continue;
    for (const std::string& line : lines.feed(port.readAvailable())) {
      const auto reply = arm::parseReply(line);
      if (!reply) continue;  // noise, or a line of something else
      if (const auto* error = std::get_if<arm::Error>(&*reply)) {
        reading.error = "the arm controller on " + port_ + " has no pose: " + error->reason;
        return reading;
      }
      if (const auto* robot_from_tool = std::get_if<RigidPose>(&*reply)) {
        reading.robot_from_tool = *robot_from_tool;
        reading.world_from_scanner =
            RigidPose::fromIsometry(robot_from_tool->isometry() * tool_from_scanner_.isometry());
        double tilt = 0.0, roll = 0.0;
        tiltAndRollOf(robot_from_tool->rotation, tilt, roll);
        reading.arm_tilt_deg = tilt;
        reading.arm_roll_deg = roll;
        return reading;
      }
    }
  }
  reading.error = "the arm controller does not answer 'POSE?' on " + port_ +
                  " (is it connected, and is it the arm's port?)";
  return reading;
}

}  // namespace clearway::hardware
