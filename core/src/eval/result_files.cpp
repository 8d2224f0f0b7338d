// Reading a `clearway-cli segment` output folder for evaluation.

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "clearway/eval/evaluation.h"
#include "clearway/io/file_util.h"
#include "clearway/io/scan_error.h"
#include "clearway/traversability/traversability_map.h"

namespace clearway::eval {
namespace {

using nlohmann::json;

// Result files larger than these are refused, not read: a labels image of 1 GiB is a map of
// 30 km x 30 km at 5 cm, a per-point class file of 4 GiB a scan of 4 billion points.
constexpr std::uint64_t kMaxLabelsImageBytes = 1ULL << 30;
constexpr std::uint64_t kMaxPointClassBytes = 1ULL << 32;
// report.json is kilobytes (its planes and parameters).
constexpr std::uint64_t kMaxReportBytes = 64ULL << 20;
// A PGM comment line is skipped up to this many characters.
constexpr std::streamsize kMaxCommentLength = 1 << 20;
// A map cell is at least this and at most that [m]: anything else is no map Clearway wrote.
constexpr double kSmallestCell = 1e-3, kLargestCell = 10.0;
// How far map_from_scanner's rotation may be from orthonormal, per entry of R^T R - I.
constexpr double kRotationTolerance = 1e-6;
// How large a map coordinate (its origin) can be [m]: a scan's maps span metres to kilometres.
constexpr double kFarthestOrigin = 1e6;

std::vector<std::uint8_t> readPgm(const std::filesystem::path& file, int& width, int& height) {
  const std::string bytes = readWholeFile(file, kMaxLabelsImageBytes);
  std::istringstream stream(bytes);
  std::string magic;
  int max_value = 0;
  stream >> magic;
  auto next_number = [&](int& value) {
    while (stream >> std::ws && stream.peek() == '#')
      stream.ignore(kMaxCommentLength, '\n');
    stream >> value;
  };
  next_number(width);
  next_number(height);
  next_number(max_value);
  if (magic != "P5" || !stream || width <= 0 || height <= 0 || max_value <= 0 || max_value > 255)
    throw std::runtime_error(file.string() + ": not a binary 8-bit PGM (P5)");
  stream.get();  // the single whitespace before the pixels
  const std::size_t offset = std::size_t(stream.tellg());
  const std::size_t count = std::size_t(width) * std::size_t(height);
  if (bytes.size() < offset + count) throw std::runtime_error(file.string() + ": truncated PGM");
  return {bytes.begin() + std::ptrdiff_t(offset), bytes.begin() + std::ptrdiff_t(offset + count)};
}

// The map frame a report gives: 16 finite numbers, a rotation and a translation (row major).
Eigen::Isometry3d mapFromScanner(const std::vector<double>& matrix,
                                 const std::function<void(const std::string&)>& fail) {
  if (matrix.size() != 16) fail("map.map_from_scanner must have 16 numbers");
  Eigen::Matrix4d m;
  for (int i = 0; i < 16; ++i) {
    if (!std::isfinite(matrix[std::size_t(i)]))
      fail("map.map_from_scanner holds a non-finite number");
    m(i / 4, i % 4) = matrix[std::size_t(i)];
  }
  const Eigen::Matrix3d rotation = m.topLeftCorner<3, 3>();
  const bool rigid =
      (rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <=
          kRotationTolerance &&
      rotation.determinant() > 0.0 && m.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1));
  if (!rigid) fail("map.map_from_scanner is not a rotation and a translation");
  if (!(m.col(3).head<3>().norm() <= kFarthestOrigin))
    fail("map.map_from_scanner moves the scanner more than 1000 km");
  Eigen::Isometry3d pose;
  pose.matrix() = m;
  return pose;
}

// A file the report names: a plain name in the result folder, which its manifest covers (a path
// out of the folder scored a map no run wrote).
std::filesystem::path fileInFolder(const std::filesystem::path& folder, const std::string& name,
                                   const std::function<void(const std::string&)>& fail) {
  const std::filesystem::path relative(name);
  if (name.empty() || relative.has_parent_path() || relative.is_absolute() || name == "." ||
      name == "..")
    fail("'" + name + "' is not a file name in the result folder");
  return folder / relative;
}

}  // namespace

SegmentationResult loadSegmentationResult(const std::filesystem::path& folder) {
  const auto report_file = folder / "report.json";
  std::string report_text;
  try {
    report_text = readWholeFile(report_file, kMaxReportBytes);  // not a pipe, a folder, a device
  } catch (const ScanError& error) {
    throw std::runtime_error(std::string(error.what()) + " (not a result folder?)");
  }
  // Values a writer bug or a hand edit put out of range were scored (a cell of 0 m, a map frame
  // of zeros: "false traversable at (-nan, -nan, -nan)"): refused, naming the key.
  const std::function<void(const std::string&)> fail = [&](const std::string& what) {
    throw std::runtime_error(report_file.string() + ": " + what);
  };
  auto positive = [&](double value, const std::string& key) {
    if (!(std::isfinite(value) && value > 0.0)) fail(key + " must be a positive number");
    return value;
  };
  SegmentationResult result;
  try {
    const json report = json::parse(report_text);
    result.scan = report.value("scan", "");
    result.ground_found = report.value("ground_found", false);
    if (report.contains("robot")) {
      const json& robot = report["robot"];
      result.robot.width = positive(robot.value("width", result.robot.width), "robot.width");
      result.robot.length = positive(robot.value("length", result.robot.length), "robot.length");
      result.robot.height = positive(robot.value("height", result.robot.height), "robot.height");
      // A step of 0 is a robot that climbs nothing (`segment --max-step 0`).
      result.robot.max_step = robot.value("max_step", result.robot.max_step);
      if (!(result.robot.max_step >= 0.0 && std::isfinite(result.robot.max_step)))
        fail("robot.max_step must be a number of at least 0");
    }
    for (const json& plane : report.value("planes", json::array())) {
      ResultPlane p;
      const auto n = plane.at("normal").get<std::vector<double>>();
      if (n.size() != 3) fail("a plane's normal must have 3 numbers");
      const Eigen::Vector3d normal(n[0], n[1], n[2]);
      if (!normal.allFinite() || normal.norm() == 0.0) fail("a plane's normal is not a direction");
      p.normal = normal.normalized();
      p.offset = plane.at("offset");
      if (!std::isfinite(p.offset)) fail("a plane's offset is not finite");
      p.kind = plane.value("kind", "");
      result.planes.push_back(p);
    }
    if (report.contains("map")) {
      const json& map = report["map"];
      result.map.resolution = map.at("resolution");
      if (!(result.map.resolution >= kSmallestCell && result.map.resolution <= kLargestCell))
        fail("map.resolution must be a cell size of 0.001-10 m");
      const auto origin = map.at("origin").get<std::vector<double>>();
      if (origin.size() != 2 || !(std::abs(origin[0]) <= kFarthestOrigin) ||
          !(std::abs(origin[1]) <= kFarthestOrigin))
        fail("map.origin must be two finite numbers (metres)");
      result.map.origin = {origin[0], origin[1]};
      result.map.map_from_scanner =
          mapFromScanner(map.at("map_from_scanner").get<std::vector<double>>(), fail);
      const auto labels_file = fileInFolder(folder, map.at("labels").get<std::string>(), fail);
      result.map.labels = readPgm(labels_file, result.map.width, result.map.height);
      if (map.value("width", result.map.width) != result.map.width ||
          map.value("height", result.map.height) != result.map.height)
        fail("map size in report.json differs from the labels image");
      for (const std::uint8_t label : result.map.labels)
        if (label > std::uint8_t(CellLabel::kStairs))
          throw std::runtime_error(labels_file.string() + ": label " + std::to_string(label) +
                                   " is none of the map's labels (0-" +
                                   std::to_string(int(CellLabel::kStairs)) + ")");
      result.has_map = true;
    }
    if (report.contains("point_classes")) {
      const auto classes_file =
          fileInFolder(folder, report["point_classes"].get<std::string>(), fail);
      const std::string bytes = readWholeFile(classes_file, kMaxPointClassBytes);
      for (std::size_t i = 0; i < bytes.size(); ++i) {
        const auto c = static_cast<unsigned char>(bytes[i]);
        if (c >= kPointClassCount)
          throw std::runtime_error(classes_file.string() + ": point " + std::to_string(i) +
                                   " has class " + std::to_string(c) + ", none of 0-" +
                                   std::to_string(kPointClassCount - 1));
        result.point_classes.push_back(PointClass(c));
      }
    }
  } catch (const json::exception& error) {
    throw std::runtime_error(report_file.string() + ": malformed (" + error.what() + ")");
  } catch (const ScanError& error) {
    throw std::runtime_error(error.what());
  }
  return result;
}

}  // namespace clearway::eval
