// The whole pipeline on an arbitrary small scan, as a reader hands one over: it must return a
// result, trusted or with a reason, without a crash, a sanitizer report or a hang; a result it
// does not trust shows nothing traversable (the safety rule), and a re-run for another robot on
// the same analysis keeps that rule too. The readers have harnesses of their own: here the
// geometry is arbitrary (all points on one spot, on one line, tens of metres apart, half of them
// no returns), not the bytes of a file. With two threads, the result must be the one thread's.
//
// Input (see encodePipelineInput in fuzz_seeds.cpp, which writes the seeds):
//   byte 0   flags: 1 the lines carry turntable angles (beta), 2 a sensor pose follows,
//            4 re-run for a narrower and taller robot, 8 also run with two threads
//   byte 1   number of lines, 1-64 (0 counts as 1)
//   [pose]   6 bytes when flag 2: roll, pitch, yaw (signed, degrees) and x, y, z (signed, dm)
//   points   x y z as little-endian int16 millimetres (-32768: no return), dealt out line by line

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <stdexcept>

#include <Eigen/Geometry>

#include "clearway/pipeline.h"
#include "clearway/scan.h"
#include "clearway/traversability/traversability_map.h"

namespace {

constexpr std::uint8_t kFlagBeta = 1, kFlagPose = 2, kFlagRerun = 4, kFlagTwoThreads = 8;
constexpr std::int16_t kNoReturn = -32768;
constexpr std::size_t kPoseBytes = 6, kPointBytes = 6;
// A few thousand points keep an execution within milliseconds under the sanitizers.
constexpr std::size_t kMostPoints = 4096;

std::int16_t int16At(const std::uint8_t* bytes) {
  return std::int16_t(std::uint16_t(bytes[0]) | std::uint16_t(bytes[1]) << 8);
}

clearway::SensorPose poseFrom(const std::uint8_t* bytes) {
  auto signedByte = [&](std::size_t k) { return double(std::int8_t(bytes[k])); };
  const double kRadians = std::numbers::pi / 180.0;
  const Eigen::Matrix3d rotation =
      (Eigen::AngleAxisd(signedByte(2) * kRadians, Eigen::Vector3d::UnitZ()) *
       Eigen::AngleAxisd(signedByte(1) * kRadians, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(signedByte(0) * kRadians, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  clearway::SensorPose pose;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      pose.rotation[std::size_t(r * 3 + c)] = rotation(r, c);
  pose.position = {signedByte(3) / 10.0, signedByte(4) / 10.0, signedByte(5) / 10.0};
  return pose;
}

// The safety rule, and a map whose arrays match its grid.
void checkResult(const clearway::PipelineResult& result) {
  using clearway::CellLabel;
  const clearway::TraversabilityMap& map = result.map;
  if (map.labels.size() != map.grid.cells() || map.reasons.size() != map.grid.cells())
    __builtin_trap();
  if (!result.trusted() && map.counts[std::size_t(CellLabel::kTraversable)] != 0) __builtin_trap();
  if (!result.trusted() && result.reason.empty()) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::uint8_t flags = data[0];
  const std::size_t lines = std::max<std::size_t>(1, std::min<std::size_t>(data[1], 64));
  std::size_t at = 2;
  clearway::Scan scan;
  if (flags & kFlagPose) {
    if (size < at + kPoseBytes) return 0;
    scan.sensor_pose = poseFrom(data + at);
    scan.pose_source = clearway::PoseSource::kFile;
    at += kPoseBytes;
  }
  const std::size_t points = std::min((size - at) / kPointBytes, kMostPoints);
  for (std::size_t i = 0; i < points; ++i, at += kPointBytes) {
    const std::int16_t x = int16At(data + at), y = int16At(data + at + 2),
                       z = int16At(data + at + 4);
    if (x == kNoReturn || y == kNoReturn || z == kNoReturn) {
      scan.points.push_back({NAN, NAN, NAN});
      scan.status.push_back(clearway::PointStatus::kNoReturn);
    } else {
      scan.points.push_back({float(x) / 1000.0F, float(y) / 1000.0F, float(z) / 1000.0F});
      scan.status.push_back(clearway::PointStatus::kValid);
    }
  }
  // The points dealt out into `lines` lines as evenly as they go (the first ones one longer).
  for (std::size_t l = 0, first = 0; l < lines && first < points; ++l) {
    clearway::ScanLine line;
    line.first = first;
    line.count = points / lines + (l < points % lines ? 1 : 0);
    if (flags & kFlagBeta) line.beta = 2.0 * std::numbers::pi * double(l) / double(lines);
    first += line.count;
    scan.lines.push_back(line);
  }

  try {
    const clearway::SegmentationParams params;
    const clearway::PipelineResult result = clearway::runPipeline(scan, params, 1);
    checkResult(result);
    if (flags & kFlagTwoThreads) {
      // Every parallel stage gathers its parts in order: the same answer as one thread's.
      const clearway::PipelineResult two = clearway::runPipeline(scan, params, 2);
      if (two.map.labels != result.map.labels || two.point_classes != result.point_classes)
        __builtin_trap();
    }
    if (flags & kFlagRerun) {
      clearway::SegmentationParams other = params;
      other.robot.width = 0.5;
      other.robot.height = 2.0;
      checkResult(clearway::rerunForRobot(scan, result.analysis, other, 1));
    }
  } catch (const std::invalid_argument&) {
    // Parameters are fixed and valid: the pipeline has no other reason to refuse a scan.
    __builtin_trap();
  }
  return 0;
}
