#include "clearway/hardware/arm_protocol.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <vector>

namespace clearway::hardware {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
// A quaternion whose length is off by more than this is a transmission or typing error, not
// rounding: refuse it rather than guess.
constexpr double kUnitTolerance = 0.01;
constexpr int kPoseValues = 7;

std::optional<RigidPose> poseFromValues(const std::vector<double>& values, std::string& error) {
  if (values.size() != std::size_t(kPoseValues)) {
    error = "a pose is 7 numbers tx,ty,tz,qw,qx,qy,qz (got " + std::to_string(values.size()) + ")";
    return std::nullopt;
  }
  for (const double value : values)
    if (!std::isfinite(value)) {
      error = "a pose must not contain NaN or infinity";
      return std::nullopt;
    }
  RigidPose pose;
  pose.translation = {values[0], values[1], values[2]};
  pose.rotation = Eigen::Quaterniond(values[3], values[4], values[5], values[6]);
  if (std::abs(pose.rotation.norm() - 1.0) > kUnitTolerance) {
    error = "the rotation quaternion qw,qx,qy,qz is not of unit length (its length is " +
            std::to_string(pose.rotation.norm()) + ")";
    return std::nullopt;
  }
  pose.rotation.normalize();
  return pose;
}

}  // namespace

Eigen::Isometry3d RigidPose::isometry() const {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  transform.linear() = rotation.toRotationMatrix();
  transform.translation() = translation;
  return transform;
}

RigidPose RigidPose::fromIsometry(const Eigen::Isometry3d& transform) {
  RigidPose pose;
  pose.translation = transform.translation();
  pose.rotation = Eigen::Quaterniond(transform.linear()).normalized();
  return pose;
}

std::optional<RigidPose> parsePose(const std::string& text, std::string& error) {
  std::vector<double> values;
  std::string item;
  std::istringstream stream(text);
  while (std::getline(stream, item, ',')) {
    std::size_t used = 0;
    try {
      values.push_back(std::stod(item, &used));
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || item.find_first_not_of(" \t", used) != std::string::npos) {
      error = "'" + item + "' in '" + text + "' is not a number";
      return std::nullopt;
    }
  }
  return poseFromValues(values, error);
}

std::string formatPose(const RigidPose& pose) {
  std::ostringstream out;
  out.precision(10);
  out << pose.translation.x() << ',' << pose.translation.y() << ',' << pose.translation.z() << ','
      << pose.rotation.w() << ',' << pose.rotation.x() << ',' << pose.rotation.y() << ','
      << pose.rotation.z();
  return out.str();
}

RigidPose defaultToolFromScanner() {
  Eigen::Matrix3d columns;
  columns.col(0) = Eigen::Vector3d::UnitZ();  // scanner x: beta = 0 looks up
  columns.col(2) = Eigen::Vector3d::UnitX();  // scanner z: the turntable axis looks forward
  columns.col(1) = columns.col(2).cross(columns.col(0));  // right-handed
  RigidPose pose;
  pose.rotation = Eigen::Quaterniond(columns).normalized();
  return pose;
}

Eigen::Quaterniond armRotation(double tilt_deg, double roll_deg) {
  return (Eigen::AngleAxisd(tilt_deg * kDeg, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll_deg * kDeg, Eigen::Vector3d::UnitX()))
      .normalized();
}

void tiltAndRollOf(const Eigen::Quaterniond& rotation, double& tilt_deg, double& roll_deg) {
  const Eigen::Matrix3d r = rotation.toRotationMatrix();
  // R = Rz(yaw) Ry(pitch) Rx(roll): r20 = -sin(pitch), r21 / r22 = tan(roll).
  tilt_deg = std::asin(std::clamp(-r(2, 0), -1.0, 1.0)) / kDeg;
  roll_deg = std::atan2(r(2, 1), r(2, 2)) / kDeg;
}

namespace arm {

std::string poseQuery() {
  return "POSE?\n";
}

std::string moveCommand(double tilt_deg, double roll_deg) {
  std::ostringstream line;
  line.precision(8);
  line << "MOVE " << tilt_deg << ' ' << roll_deg << "\n";
  return line.str();
}

std::string poseReply(const RigidPose& robot_from_tool) {
  std::ostringstream line;
  line.precision(10);
  const auto& t = robot_from_tool.translation;
  const auto& q = robot_from_tool.rotation;
  line << "POSE " << t.x() << ' ' << t.y() << ' ' << t.z() << ' ' << q.w() << ' ' << q.x() << ' '
       << q.y() << ' ' << q.z() << "\n";
  return line.str();
}

std::optional<Reply> parseReply(const std::string& line) {
  std::istringstream words(line);
  std::string keyword;
  if (!(words >> keyword)) return std::nullopt;
  if (const auto acknowledgement = line_protocol::parseAcknowledgement(line))
    return std::visit([](const auto& reply) { return Reply(reply); }, *acknowledgement);
  if (keyword != "POSE") return std::nullopt;
  std::vector<double> values;
  std::string word;
  while (words >> word) {
    std::size_t used = 0;
    try {
      values.push_back(std::stod(word, &used));
    } catch (const std::exception&) {
      return std::nullopt;
    }
    if (used != word.size()) return std::nullopt;
  }
  std::string error;
  const auto pose = poseFromValues(values, error);
  if (!pose) return std::nullopt;
  return *pose;
}

}  // namespace arm
}  // namespace clearway::hardware
