#include "clearway/pose.h"

#include <Eigen/Geometry>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "clearway/io/file_util.h"
#include "clearway/io/scan_error.h"

namespace clearway {
namespace {

// Sidecars are a few hundred bytes; anything much larger is not one.
constexpr std::uintmax_t kMaxSidecarBytes = 64 * 1024;

std::vector<double> parseNumberList(const std::string& text, std::size_t count,
                                    const std::string& what) {
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    std::size_t used = 0;
    double value = 0.0;
    try {
      value = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || item.find_first_not_of(" \t", used) != std::string::npos)
      throw std::invalid_argument(what + ": '" + item + "' is not a number");
    if (!std::isfinite(value)) throw std::invalid_argument(what + ": values must be finite");
    values.push_back(value);
  }
  if (values.size() != count)
    throw std::invalid_argument(what + ": expected " + std::to_string(count) +
                                " comma-separated numbers, got " + std::to_string(values.size()));
  return values;
}

SensorPose fromIsometry(const Eigen::Isometry3d& pose) {
  SensorPose result;
  for (int r = 0; r < 3; ++r) {
    result.position[std::size_t(r)] = pose.translation()[r];
    for (int c = 0; c < 3; ++c)
      result.rotation[std::size_t(3 * r + c)] = pose.linear()(r, c);
  }
  return result;
}

}  // namespace

std::string_view poseSourceName(PoseSource source) {
  switch (source) {
    case PoseSource::kNone:
      return "none";
    case PoseSource::kFile:
      return "file";
    case PoseSource::kSidecar:
      return "sidecar";
    case PoseSource::kCommandLine:
      return "command line";
    case PoseSource::kOperator:
      return "operator";
    case PoseSource::kEstimated:
      return "estimated";
  }
  return "none";
}

SensorPose poseFromQuaternion(const Eigen::Vector3d& translation, double qw, double qx, double qy,
                              double qz) {
  Eigen::Quaterniond q(qw, qx, qy, qz);
  if (!std::isfinite(q.norm()) || q.norm() < 1e-9)
    throw std::invalid_argument("the rotation quaternion has zero length or is not finite");
  q.normalize();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = q.toRotationMatrix();
  pose.translation() = translation;
  return fromIsometry(pose);
}

SensorPose parsePoseText(const std::string& text) {
  const std::vector<double> v = parseNumberList(text, 7, "--pose tx,ty,tz,qw,qx,qy,qz");
  try {
    return poseFromQuaternion({v[0], v[1], v[2]}, v[3], v[4], v[5], v[6]);
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument(std::string("--pose: ") + error.what());
  }
}

Eigen::Vector3d parseUpText(const std::string& text) {
  const std::vector<double> v = parseNumberList(text, 3, "--up X,Y,Z");
  const Eigen::Vector3d up(v[0], v[1], v[2]);
  if (up.norm() < 1e-9) throw std::invalid_argument("--up X,Y,Z: the direction has zero length");
  return up.normalized();
}

SensorPose poseFromUp(const Eigen::Vector3d& up) {
  const Eigen::Vector3d z = up.normalized();
  // World x: the scanner's x axis laid flat (its y when x is nearly vertical).
  Eigen::Vector3d x = Eigen::Vector3d::UnitX() - z.x() * z;
  if (x.norm() < 0.3) x = Eigen::Vector3d::UnitY() - z.y() * z;
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Isometry3d world_from_scanner = Eigen::Isometry3d::Identity();
  world_from_scanner.linear().row(0) = x.transpose();
  world_from_scanner.linear().row(1) = y.transpose();
  world_from_scanner.linear().row(2) = z.transpose();
  return fromIsometry(world_from_scanner);
}

std::optional<std::filesystem::path> findPoseSidecar(const std::filesystem::path& scan_file) {
  std::filesystem::path replaced = scan_file;
  replaced.replace_extension(".pose.json");
  std::filesystem::path kept = scan_file;
  kept += ".pose.json";
  for (const auto& candidate : {replaced, kept}) {
    std::error_code error;
    if (std::filesystem::exists(candidate, error)) return candidate;
  }
  return std::nullopt;
}

SensorPose readPoseSidecar(const std::filesystem::path& file) {
  const std::string text = readWholeFile(file, kMaxSidecarBytes);
  try {
    const nlohmann::json json = nlohmann::json::parse(text);
    const nlohmann::json& pose = json.at("world_from_scanner");
    const auto t = pose.at("translation").get<std::vector<double>>();
    const auto q = pose.at("rotation_wxyz").get<std::vector<double>>();
    if (t.size() != 3 || q.size() != 4)
      throw ScanError(file, "translation needs 3 numbers and rotation_wxyz 4");
    for (double value : t)
      if (!std::isfinite(value)) throw ScanError(file, "the translation is not finite");
    return poseFromQuaternion({t[0], t[1], t[2]}, q[0], q[1], q[2], q[3]);
  } catch (const ScanError&) {
    throw;
  } catch (const std::exception& error) {
    throw ScanError(file, std::string("not a pose sidecar: ") + error.what());
  }
}

void writePoseSidecar(const SensorPose& pose, const std::string& source,
                      const std::filesystem::path& file) {
  Eigen::Matrix3d rotation;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      rotation(r, c) = pose.rotation[std::size_t(3 * r + c)];
  const Eigen::Quaterniond q(rotation);
  nlohmann::json json;
  json["version"] = 1;
  json["source"] = source;
  json["world_from_scanner"] = {
      {"translation", {pose.position[0], pose.position[1], pose.position[2]}},
      {"rotation_wxyz", {q.w(), q.x(), q.y(), q.z()}}};
  writeTextFileAtomically(file, json.dump(2) + "\n");
}

PoseResolution resolveScanPose(Scan& scan, const PoseRequest& request) {
  if (request.pose) {
    scan.sensor_pose = *request.pose;
    scan.pose_source = PoseSource::kCommandLine;
    return {PoseSource::kCommandLine, "--pose"};
  }
  if (request.up) {
    scan.sensor_pose = poseFromUp(*request.up);
    scan.pose_source = PoseSource::kCommandLine;
    return {PoseSource::kCommandLine, "--up"};
  }
  if (request.use_sidecar && !scan.metadata.source_path.empty()) {
    if (const auto sidecar = findPoseSidecar(scan.metadata.source_path)) {
      scan.sensor_pose = readPoseSidecar(*sidecar);
      scan.pose_source = PoseSource::kSidecar;
      return {PoseSource::kSidecar, sidecar->string()};
    }
  }
  if (scan.sensor_pose) {
    scan.pose_source = PoseSource::kFile;
    return {PoseSource::kFile, scan.metadata.format};
  }
  scan.pose_source = PoseSource::kNone;
  return {PoseSource::kNone, "no pose in the file, no sidecar, none given"};
}

}  // namespace clearway
