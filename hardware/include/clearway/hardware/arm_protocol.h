#pragma once

// Clearway's arm protocol (docs/ARM.md): the robot's arm controller tells where the tool flange
// carrying the RoSi is, so every scan gets the pose it was taken from (paper, section II: the RoSi
// is carried by the arm, its orientation changes from scan to scan).
//
//   host -> arm: POSE?                      | MOVE <tilt_deg> <roll_deg>   (one per line, '\n')
//   arm -> host: POSE tx ty tz qw qx qy qz  | OK MOVE | ERR <reason>
//
// POSE is robot_from_tool: metres and a unit quaternion, the robot frame x forward, y left, z up.

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <variant>

#include "clearway/hardware/line_protocol.h"

namespace clearway::hardware {

// A rigid transform as the protocols and files write it: a translation and a unit quaternion.
struct RigidPose {
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();

  Eigen::Isometry3d isometry() const;
  static RigidPose fromIsometry(const Eigen::Isometry3d& transform);
};

// Parses "tx,ty,tz,qw,qx,qy,qz" (as --mount and PCD VIEWPOINT order them). Returns nullopt and a
// reason in `error` for anything else: a wrong count, a non-number, a non-finite value, a
// quaternion far from unit length (it is normalised when within 1 %).
std::optional<RigidPose> parsePose(const std::string& text, std::string& error);

// "tx,ty,tz,qw,qx,qy,qz" with enough digits to read back the same pose.
std::string formatPose(const RigidPose& pose);

// How the RoSi sits on the tool flange unless configured otherwise (tool_from_scanner): the
// turntable axis (scanner z) along the tool's x (forward), the line at beta = 0 (scanner x)
// along the tool's z (up), no offset.
RigidPose defaultToolFromScanner();

// The tool's orientation for an arm tilt (pitch about the robot's y axis, positive nose down)
// and roll (about the tool's own x axis): R = Ry(tilt) * Rx(roll), the usual yaw-pitch-roll
// order with no yaw.
Eigen::Quaterniond armRotation(double tilt_deg, double roll_deg);
// The tilt and roll of a rotation in that order (its yaw is ignored).
void tiltAndRollOf(const Eigen::Quaterniond& rotation, double& tilt_deg, double& roll_deg);

namespace arm {

std::string poseQuery();                                    // "POSE?\n"
std::string moveCommand(double tilt_deg, double roll_deg);  // "MOVE <tilt> <roll>\n"
std::string poseReply(const RigidPose& robot_from_tool);    // "POSE tx ty tz qw qx qy qz\n"

using line_protocol::Error;
using line_protocol::Ok;
using Reply = std::variant<RigidPose, Ok, Error>;
// Parses one line (without its '\n'); nullopt for a line that is no reply or a malformed POSE.
std::optional<Reply> parseReply(const std::string& line);

}  // namespace arm
}  // namespace clearway::hardware
