// Reading a `clearway-cli segment` output folder for evaluation.

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "clearway/eval/evaluation.h"
#include "clearway/io/file_util.h"
#include "clearway/io/scan_error.h"

namespace clearway::eval {
namespace {

using nlohmann::json;

// Result files larger than these are refused, not read: a labels image of 1 GiB is a map of
// 30 km x 30 km at 5 cm, a per-point class file of 4 GiB a scan of 4 billion points.
constexpr std::uint64_t kMaxLabelsImageBytes = 1ULL << 30;
constexpr std::uint64_t kMaxPointClassBytes = 1ULL << 32;
// A PGM comment line is skipped up to this many characters.
constexpr std::streamsize kMaxCommentLength = 1 << 20;

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

}  // namespace

SegmentationResult loadSegmentationResult(const std::filesystem::path& folder) {
  const auto report_file = folder / "report.json";
  std::ifstream stream(report_file);
  if (!stream)
    throw std::runtime_error(report_file.string() + ": cannot open (not a result folder?)");
  SegmentationResult result;
  try {
    const json report = json::parse(stream);
    result.ground_found = report.value("ground_found", false);
    if (report.contains("robot")) {
      const json& robot = report["robot"];
      result.robot.width = robot.value("width", result.robot.width);
      result.robot.length = robot.value("length", result.robot.length);
      result.robot.height = robot.value("height", result.robot.height);
      result.robot.max_step = robot.value("max_step", result.robot.max_step);
    }
    for (const json& plane : report.value("planes", json::array())) {
      ResultPlane p;
      const auto n = plane.at("normal").get<std::vector<double>>();
      if (n.size() != 3) throw std::runtime_error("plane normal must have 3 numbers");
      p.normal = Eigen::Vector3d(n[0], n[1], n[2]).normalized();
      p.offset = plane.at("offset");
      p.kind = plane.value("kind", "");
      result.planes.push_back(p);
    }
    if (report.contains("map")) {
      const json& map = report["map"];
      result.map.resolution = map.at("resolution");
      const auto origin = map.at("origin").get<std::vector<double>>();
      result.map.origin = {origin.at(0), origin.at(1)};
      const auto matrix = map.at("map_from_scanner").get<std::vector<double>>();
      if (matrix.size() != 16) throw std::runtime_error("map_from_scanner must have 16 numbers");
      Eigen::Matrix4d m;
      for (int i = 0; i < 16; ++i)
        m(i / 4, i % 4) = matrix[std::size_t(i)];
      result.map.map_from_scanner.matrix() = m;
      result.map.labels = readPgm(folder / map.at("labels").get<std::string>(), result.map.width,
                                  result.map.height);
      if (map.value("width", result.map.width) != result.map.width ||
          map.value("height", result.map.height) != result.map.height)
        throw std::runtime_error("map size in report.json differs from the labels image");
      result.has_map = true;
    }
    if (report.contains("point_classes")) {
      const std::string bytes =
          readWholeFile(folder / report["point_classes"].get<std::string>(), kMaxPointClassBytes);
      for (unsigned char c : bytes) {
        if (c >= kPointClassCount) throw std::runtime_error("point class out of range");
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
