#pragma once

// Where the scanner was when it scanned: one resolution for every caller (segment, bench, info,
// the console), so the same scan is read the same way everywhere. The RoSi rides on the robot's
// arm (paper, section II), so its orientation changes from scan to scan and must come with the
// scan, or be estimated from it (docs/ALGORITHM.md, "Up direction without a pose").

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "clearway/scan.h"

namespace clearway {

std::string_view poseSourceName(PoseSource source);

// What the operator asked for. Empty optionals leave the lower sources in charge.
struct PoseRequest {
  std::optional<SensorPose> pose;     // --pose tx,ty,tz,qw,qx,qy,qz (world_from_scanner)
  std::optional<Eigen::Vector3d> up;  // --up X,Y,Z: world up seen in the scanner frame
  bool use_sidecar = true;
};

struct PoseResolution {
  PoseSource source = PoseSource::kNone;
  std::string detail;  // e.g. the sidecar's path, or what the command line said
};

// Applies the precedence to `scan` (sets scan.sensor_pose and scan.pose_source) and says what
// won. Throws ScanError for an unreadable sidecar: a pose file that exists but cannot be read must
// never be skipped silently, since the next source down may be wrong.
PoseResolution resolveScanPose(Scan& scan, const PoseRequest& request);

// "tx,ty,tz,qw,qx,qy,qz" (quaternion normalised; refused when not finite or of zero length).
// Throws std::invalid_argument with a readable reason.
SensorPose parsePoseText(const std::string& text);
// "X,Y,Z", normalised. Throws std::invalid_argument.
Eigen::Vector3d parseUpText(const std::string& text);

// A pose whose world z is `up` (a unit vector in the scanner frame), yaw chosen from the scanner's
// x axis: what an up direction alone says about world_from_scanner.
SensorPose poseFromUp(const Eigen::Vector3d& up);
// `v` scaled to unit length, or nullopt when it is not finite or shorter than `smallest`. Divided
// by its largest component first: the norm of components of 1e200 overflowed, and `--up 1e200,0,0`
// became the zero vector, accepted.
std::optional<Eigen::Vector3d> unitDirection(const Eigen::Vector3d& v, double smallest = 1e-9);

// Throws std::invalid_argument when (qw, qx, qy, qz) is zero or not finite (unitQuaternion).
SensorPose poseFromQuaternion(const Eigen::Vector3d& translation, double qw, double qx, double qy,
                              double qz);

// Scales `q` (its four components in any order) to unit length; false, leaving it as it was, when
// a component is not finite or the largest is below `smallest` (zero but for rounding). Divided
// by its largest component first: the norm of components of 1e200 overflows to infinity, and
// dividing by that made every component 0, the identity rotation, without a word.
bool unitQuaternion(std::array<double, 4>& q, double smallest = 1e-9);

// The sidecars resolution looks for, in order: SCAN.pose.json with the scan's extension replaced,
// then with it kept (garage.pose.json, garage.pcd.pose.json).
std::optional<std::filesystem::path> findPoseSidecar(const std::filesystem::path& scan_file);
// Reads {"world_from_scanner": {"translation": [x,y,z], "rotation_wxyz": [w,x,y,z]}}.
// Throws ScanError naming the file for anything else.
SensorPose readPoseSidecar(const std::filesystem::path& file);
// Writes the same format atomically; `source` names what the pose came from (e.g. "arm").
void writePoseSidecar(const SensorPose& pose, const std::string& source,
                      const std::filesystem::path& file);

}  // namespace clearway
