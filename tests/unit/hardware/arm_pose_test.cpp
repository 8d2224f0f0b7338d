// The arm's pose: the protocol, the tilt/roll convention, the mounting, and the emulated arm
// reporting the pose it really holds the scanner at.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "clearway/hardware/arm_protocol.h"
#include "clearway/hardware/pose_source.h"
#include "clearway/hardware/rosi_emulator.h"
#include "clearway/sim/builtin_scenes.h"

namespace clearway::hardware {
namespace {

TEST(ArmProtocol, PosesParseAndBadOnesAreRefusedWithAReason) {
  std::string error;
  const auto pose = parsePose("0.1,0.2,1.5,1,0,0,0", error);
  ASSERT_TRUE(pose) << error;
  EXPECT_DOUBLE_EQ(pose->translation.z(), 1.5);
  EXPECT_FALSE(parsePose("1,2,3", error));
  EXPECT_NE(error.find("7 numbers"), std::string::npos) << error;
  EXPECT_FALSE(parsePose("0,0,0,2,0,0,0", error));
  EXPECT_NE(error.find("unit length"), std::string::npos) << error;
  EXPECT_FALSE(parsePose("0,0,nan,1,0,0,0", error));
  EXPECT_FALSE(parsePose("0,0,x,1,0,0,0", error));
  EXPECT_NE(error.find("'x'"), std::string::npos) << error;
}

TEST(ArmProtocol, RepliesParse) {
  const auto pose = arm::parseReply("POSE 0.5 -0.5 1.2 1 0 0 0");
  ASSERT_TRUE(pose && std::holds_alternative<RigidPose>(*pose));
  EXPECT_DOUBLE_EQ(std::get<RigidPose>(*pose).translation.y(), -0.5);
  EXPECT_FALSE(arm::parseReply("POSE 0.5 -0.5 1.2 1 0 0"));    // a cut line
  EXPECT_FALSE(arm::parseReply("POSE 0.5 -0.5 1.2 5 0 0 0"));  // no rotation
  const auto error = arm::parseReply("ERR arm is moving");
  ASSERT_TRUE(error && std::holds_alternative<arm::Error>(*error));
  EXPECT_EQ(std::get<arm::Error>(*error).reason, "arm is moving");
  // What the arm sends reads back as the same pose.
  RigidPose sent;
  sent.translation = {0.3, 0.1, 1.1};
  sent.rotation = armRotation(30, 60);
  std::string line = arm::poseReply(sent);
  line.pop_back();
  const auto back = arm::parseReply(line);
  ASSERT_TRUE(back);
  EXPECT_TRUE(std::get<RigidPose>(*back).isometry().isApprox(sent.isometry(), 1e-9));
}

TEST(ArmProtocol, TiltPitchesTheToolNoseDownAndRollTurnsItAboutItsOwnAxis) {
  const Eigen::Vector3d forward = armRotation(30, 0) * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(forward.z(), -0.5, 1e-12);  // nose down
  EXPECT_TRUE((armRotation(30, 60) * Eigen::Vector3d::UnitX()).isApprox(forward, 1e-12));
  double tilt = 0, roll = 0;
  tiltAndRollOf(armRotation(30, 60), tilt, roll);
  EXPECT_NEAR(tilt, 30, 1e-9);
  EXPECT_NEAR(roll, 60, 1e-9);
  // The default mounting points the turntable axis (scanner z) along the tool's x.
  const Eigen::Isometry3d mounting = defaultToolFromScanner().isometry();
  EXPECT_TRUE(mounting.linear().col(2).isApprox(Eigen::Vector3d::UnitX(), 1e-12));
  EXPECT_TRUE(mounting.linear().col(0).isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
}

TEST(ArmPoseSource, TheEmulatedArmReportsWhereItHoldsTheScannerAndMovesBetweenScans) {
  EmulatorOptions options{20.0, 3};
  options.arm_tilt_deg = 30;
  options.arm_roll_deg = 60;
  RosiEmulator emulator(*sim::builtinScene("garage"), options);
  ArmPoseSource arm(emulator.armPort());
  const PoseReading reading = arm.read(1000);
  ASSERT_TRUE(reading.ok()) << reading.error;
  EXPECT_EQ(reading.source, "arm");
  EXPECT_NEAR(*reading.arm_tilt_deg, 30, 1e-6);
  EXPECT_NEAR(*reading.arm_roll_deg, 60, 1e-6);
  EXPECT_FALSE(reading.time.empty());
  EXPECT_TRUE(
      reading.world_from_scanner.isometry().isApprox(emulator.worldFromScanner().isometry(), 1e-6));
  EXPECT_NEAR(reading.world_from_scanner.translation.z(), 1.2,
              1e-9);  // the garage's scanner height

  // Between scans the arm moves (MOVE on its port, as `printf 'MOVE -10 5\n' > PORT` does).
  {
    const int port = ::open(emulator.armPort().c_str(), O_RDWR | O_NOCTTY);
    ASSERT_GE(port, 0);
    const std::string move = arm::moveCommand(-10, 5);
    ASSERT_EQ(::write(port, move.data(), move.size()), ssize_t(move.size()));
    ::close(port);
  }
  const PoseReading moved = arm.read(1000);
  ASSERT_TRUE(moved.ok()) << moved.error;
  EXPECT_NEAR(*moved.arm_tilt_deg, -10, 1e-6);
  EXPECT_NEAR(*moved.arm_roll_deg, 5, 1e-6);
  emulator.moveArm(12, -3);
  EXPECT_NEAR(*arm.read(1000).arm_tilt_deg, 12, 1e-6);
}

TEST(ArmPoseSource, NoArmAndAFixedMountingAreToldApart) {
  ArmPoseSource missing("/dev/clearway-no-arm");
  const PoseReading none = missing.read(100);
  EXPECT_FALSE(none.ok());
  EXPECT_NE(none.error.find("/dev/clearway-no-arm"), std::string::npos) << none.error;
  RigidPose mounting;
  mounting.translation = {0.2, 0.0, 0.9};
  FixedMounting fixed(mounting);
  const PoseReading reading = fixed.read(0);
  ASSERT_TRUE(reading.ok());
  EXPECT_EQ(reading.source, "mounting");
  EXPECT_FALSE(reading.arm_tilt_deg);
  EXPECT_DOUBLE_EQ(reading.world_from_scanner.translation.z(), 0.9);
}

}  // namespace
}  // namespace clearway::hardware
