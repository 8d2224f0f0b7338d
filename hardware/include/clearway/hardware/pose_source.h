#pragma once

// Where the RoSi is when a scan starts: world_from_scanner, for the scan's VIEWPOINT and its
// SCAN.pose.json sidecar. The robot frame is the world of a scan-and-stop robot standing on its
// floor. Two sources: a fixed mounting from the settings (robot_from_scanner), and the arm
// controller (docs/ARM.md) composed with the RoSi's mounting on the tool flange:
// robot_from_scanner = robot_from_tool * tool_from_scanner.
//
// Like ScannerDevice, the public API is non-virtual (it checks what a source returns) and the
// implementations override protected hooks.

#include <optional>
#include <string>

#include "clearway/hardware/arm_protocol.h"
#include "clearway/scan.h"

namespace clearway::hardware {

struct PoseReading {
  RigidPose world_from_scanner;
  std::string source;  // "arm" or "mounting"
  // From the arm only: what it reported, and its tilt and roll (arm_protocol.h's convention).
  std::optional<RigidPose> robot_from_tool;
  std::optional<double> arm_tilt_deg, arm_roll_deg;
  std::string time;   // when it was read, ISO 8601 UTC (e.g. 2026-11-22T21:05:00Z)
  std::string error;  // non-empty: no pose, and why (operator-readable)
  bool ok() const { return error.empty(); }
};

// The pose as a Scan carries it (and PCD VIEWPOINT writes it).
SensorPose sensorPoseOf(const RigidPose& world_from_scanner);

class PoseSource {
 public:
  virtual ~PoseSource() = default;
  // The pose now. Never throws; a source that fails, or returns a non-finite or non-unit pose,
  // gives a reading with `error` set.
  PoseReading read(int timeout_ms);
  std::string description() const { return doDescribe(); }

 protected:
  virtual PoseReading doRead(int timeout_ms) = 0;
  virtual std::string doDescribe() const = 0;
};

// A scanner fixed on the robot: the pose never changes.
class FixedMounting : public PoseSource {
 public:
  explicit FixedMounting(RigidPose robot_from_scanner) : mounting_(robot_from_scanner) {}

 protected:
  PoseReading doRead(int timeout_ms) override;
  std::string doDescribe() const override;

 private:
  RigidPose mounting_;
};

// The arm controller on a serial port, asked "POSE?" for every scan. The port is opened (and
// locked) only while asking, so the console can keep the object between scans.
class ArmPoseSource : public PoseSource {
 public:
  ArmPoseSource(std::string port, RigidPose tool_from_scanner = defaultToolFromScanner());
  const RigidPose& toolFromScanner() const { return tool_from_scanner_; }

 protected:
  PoseReading doRead(int timeout_ms) override;
  std::string doDescribe() const override;

 private:
  std::string port_;
  RigidPose tool_from_scanner_;
};

}  // namespace clearway::hardware
