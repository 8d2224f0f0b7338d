#include "clearway/pose.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "clearway/io/file_util.h"
#include "clearway/io/scan_error.h"
#include "io/strict_json.h"

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

std::optional<Eigen::Vector3d> unitDirection(const Eigen::Vector3d& v, double smallest) {
  if (!v.allFinite()) return std::nullopt;
  const double largest = v.cwiseAbs().maxCoeff();
  if (largest == 0.0) return std::nullopt;
  const Eigen::Vector3d scaled = v / largest;  // within [-1, 1]: its norm cannot overflow
  if (largest * scaled.norm() < smallest) return std::nullopt;
  return scaled.normalized();
}

bool unitQuaternion(std::array<double, 4>& q, double smallest) {
  double largest = 0.0;
  for (const double component : q) {
    if (!std::isfinite(component)) return false;
    largest = std::max(largest, std::abs(component));
  }
  if (largest < smallest) return false;
  std::array<double, 4> scaled = q;
  double norm_squared = 0.0;
  for (double& component : scaled) {
    component /= largest;  // now within [-1, 1], one of them +-1: the norm cannot overflow
    norm_squared += component * component;
  }
  const double norm = std::sqrt(norm_squared);
  for (std::size_t k = 0; k < q.size(); ++k)
    q[k] = scaled[k] / norm;
  return true;
}

SensorPose poseFromQuaternion(const Eigen::Vector3d& translation, double qw, double qx, double qy,
                              double qz) {
  std::array<double, 4> unit{qw, qx, qy, qz};
  if (!unitQuaternion(unit))
    throw std::invalid_argument("the rotation quaternion has zero length or is not finite");
  const Eigen::Quaterniond q(unit[0], unit[1], unit[2], unit[3]);
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
  const auto up = unitDirection({v[0], v[1], v[2]});
  if (!up) throw std::invalid_argument("--up X,Y,Z: the direction has zero length");
  return *up;
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
  std::vector<std::filesystem::path> found;
  for (const auto& candidate : {replaced, kept}) {
    // The link itself, not what it points to: a sidecar that is a broken link or a link loop is
    // a sidecar that cannot be read (readPoseSidecar says why), not no sidecar at all.
    std::error_code error;
    if (std::filesystem::exists(std::filesystem::symlink_status(candidate, error)))
      found.push_back(candidate);
  }
  // Two poses for one scan: which one is right is the operator's to say, not ours to pick.
  if (found.size() == 2)
    throw ScanError(scan_file, "two pose sidecars, " + found[0].filename().string() + " and " +
                                   found[1].filename().string() + ": keep the right one");
  if (found.empty()) return std::nullopt;
  return found.front();
}

namespace {

constexpr int kSidecarVersion = 1;
// How far from the origin a sidecar may put the scanner [m]: as far as any scanner measures.
constexpr double kFarthestSidecarTranslation = 10'000.0;
// How far from 1 a sidecar's quaternion may be long: rounding in the writer's digits.
constexpr double kQuaternionLengthTolerance = 1e-3;

// The sidecar's JSON, refusing a key given twice in one object (parseStrictJson).
nlohmann::json parseSidecar(const std::filesystem::path& file, const std::string& text) {
  try {
    return detail::parseStrictJson(text);
  } catch (const std::invalid_argument& error) {
    throw ScanError(file, error.what());
  }
}

// `count` finite numbers under `key` of `object`.
std::vector<double> numbers(const std::filesystem::path& file, const nlohmann::json& object,
                            const char* key, std::size_t count) {
  if (!object.is_object() || !object.contains(key))
    throw ScanError(file, std::string("no \"") + key + "\"");
  const nlohmann::json& values = object.at(key);
  if (!values.is_array() || values.size() != count)
    throw ScanError(file,
                    std::string("\"") + key + "\" needs " + std::to_string(count) + " numbers");
  std::vector<double> result;
  for (const nlohmann::json& value : values) {
    if (!value.is_number() || !std::isfinite(value.get<double>())) {
      // As much of it as a message line holds: a deeply nested value gave a 60 kB line.
      constexpr std::size_t kShown = 40;
      std::string shown = value.dump();
      if (shown.size() > kShown) shown = shown.substr(0, kShown) + "...";
      throw ScanError(file,
                      std::string("\"") + key + "\" holds " + shown + ", not a finite number");
    }
    result.push_back(value.get<double>());
  }
  return result;
}

}  // namespace

SensorPose readPoseSidecar(const std::filesystem::path& file) {
  const std::string text = readWholeFile(file, kMaxSidecarBytes);
  nlohmann::json json;
  try {
    json = parseSidecar(file, text);
  } catch (const ScanError&) {
    throw;
  } catch (const std::exception& error) {
    throw ScanError(file, std::string("not a pose sidecar: ") + error.what());
  }
  if (!json.is_object()) throw ScanError(file, "not a pose sidecar: not a JSON object");
  // A later version may mean something else by the same keys: refused, not guessed at.
  if (!json.contains("version") || !json.at("version").is_number_integer() ||
      json.at("version").get<long long>() != kSidecarVersion)
    throw ScanError(
        file, "pose sidecar version " +
                  (json.contains("version") ? json.at("version").dump() : std::string("missing")) +
                  ": this Clearway reads version " + std::to_string(kSidecarVersion));
  if (json.contains("source") && !json.at("source").is_string())
    throw ScanError(file, "\"source\" must be text");
  if (!json.contains("world_from_scanner"))
    throw ScanError(file, "not a pose sidecar: no \"world_from_scanner\"");
  const nlohmann::json& pose = json.at("world_from_scanner");
  const std::vector<double> t = numbers(file, pose, "translation", 3);
  const std::vector<double> q = numbers(file, pose, "rotation_wxyz", 4);
  // The scanner's place on a robot or in a room: metres, not 1e308 (the 3D view went blank, the
  // robot off the map, every cell out of reach, the panel saying "Ground found").
  if (!(Eigen::Vector3d(t[0], t[1], t[2]).cwiseAbs().maxCoeff() <= kFarthestSidecarTranslation))
    throw ScanError(file, "\"translation\" puts the scanner more than 10 km away");
  // Writers give a unit quaternion; one of length 2 or 1e-8 is a wrong one, not rounding (the
  // journal's POSE record is held to the same).
  const double length = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!(std::abs(length - 1.0) <= kQuaternionLengthTolerance))
    throw ScanError(file, "\"rotation_wxyz\" has length " + std::to_string(length) +
                              ", not 1: not a rotation as written");
  try {
    return poseFromQuaternion({t[0], t[1], t[2]}, q[0], q[1], q[2], q[3]);
  } catch (const std::invalid_argument& error) {
    throw ScanError(file, error.what());
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
