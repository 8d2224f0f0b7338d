// Plain ASCII point lists: XYZ/TXT/DAT ("x y z [intensity]", metres) and 3DTK's "uos" .3d
// (centimetres, left-handed, y up) with its .pose sidecar.

#include <cmath>
#include <cstring>
#include <fstream>
#include <numbers>

#include "ascii_rows.h"
#include "clearway/io/file_util.h"
#include "readers.h"

namespace clearway::detail {
namespace {

constexpr std::uintmax_t kMaxAsciiBytes = 8ULL << 30;

std::string readAsciiScan(const std::filesystem::path& file, const LoadOptions& options) {
  std::string text = readWholeFile(file, kMaxAsciiBytes);
  if (text.find('\0') != std::string::npos)
    throw ScanError(file, "binary data in a text point file (wrong extension?)");
  (void)options;
  return text;
}

// 3DTK angles are degrees; its rotation is R = Rx(rx) * Ry(ry) * Rz(rz) applied in its left-handed
// frame. Clearway's frame is c = C * u with C mapping (x, y, z)_uos to (z, -x, y); the same
// rotation seen from our frame is C * R * C^T.
SensorPose uosPoseToClearway(const std::array<double, 6>& uos) {
  const double to_rad = std::numbers::pi / 180.0;
  const double a = uos[3] * to_rad, b = uos[4] * to_rad, c = uos[5] * to_rad;
  const double sa = std::sin(a), ca = std::cos(a), sb = std::sin(b), cb = std::cos(b);
  const double sc = std::sin(c), cc = std::cos(c);
  const double r[9] = {cb * cc,
                       -cb * sc,
                       sb,
                       sa * sb * cc + ca * sc,
                       -sa * sb * sc + ca * cc,
                       -sa * cb,
                       -ca * sb * cc + sa * sc,
                       ca * sb * sc + sa * cc,
                       ca * cb};
  // C rows: (0,0,1), (-1,0,0), (0,1,0): C*R*C^T picks and signs entries of R.
  static constexpr int kAxis[3] = {2, 0, 1};
  static constexpr double kSign[3] = {1.0, -1.0, 1.0};
  SensorPose pose;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      pose.rotation[std::size_t(3 * i + j)] = kSign[i] * kSign[j] * r[3 * kAxis[i] + kAxis[j]];
  pose.position = {uos[2] / 100.0, -uos[0] / 100.0, uos[1] / 100.0};
  return pose;
}

std::optional<SensorPose> readUosPose(const std::filesystem::path& scan_file) {
  std::filesystem::path pose_file = scan_file;
  pose_file.replace_extension(".pose");
  std::ifstream stream(pose_file);
  if (!stream) return std::nullopt;
  std::array<double, 6> values{};
  for (double& value : values)
    if (!(stream >> value)) throw ScanError(pose_file, "expected 'tx ty tz' and 'rx ry rz'");
  return uosPoseToClearway(values);
}

// Text rows "x y z [intensity]", each turned into Clearway's frame by `convert`.
Scan readTextPoints(const std::filesystem::path& file, const LoadOptions& options,
                    Point3f (*convert)(const std::array<double, 4>&)) {
  const std::string text = readAsciiScan(file, options);
  Scan scan;
  bool has_intensity = false;
  parseNumberRows(
      file, text, 3,
      [&](const std::array<double, 4>& v, std::size_t columns) {
        if (scan.size() >= options.max_points)
          throw ScanError(file,
                          "more points than the limit of " + std::to_string(options.max_points));
        if (scan.empty()) has_intensity = columns >= 4;
        const Point3f p = convert(v);
        appendPoint(scan, p.x, p.y, p.z);
        if (has_intensity) scan.intensity.push_back(columns >= 4 ? float(v[3]) : 0.0F);
      },
      options.progress);
  return scan;
}

}  // namespace

Scan readXyz(const std::filesystem::path& file, const LoadOptions& options) {
  Scan scan = readTextPoints(file, options, [](const std::array<double, 4>& v) {
    return Point3f{float(v[0]), float(v[1]), float(v[2])};
  });
  scan.metadata.format = "xyz ascii";
  scan.metadata.frame = "as stored: metres";
  return scan;
}

Scan readUos(const std::filesystem::path& file, const LoadOptions& options) {
  // (x, y, z)_clearway = (z, -x, y)_uos / 100
  Scan scan = readTextPoints(file, options, [](const std::array<double, 4>& v) {
    return Point3f{float(v[2] / 100.0), float(-v[0] / 100.0), float(v[1] / 100.0)};
  });
  scan.sensor_pose = readUosPose(file);
  scan.metadata.format = "3dtk uos";
  scan.metadata.frame = "3DTK uos (cm, left-handed, y up) -> (z, -x, y) / 100: metres, z up";
  return scan;
}

Scan readKittiBin(const std::filesystem::path& file, const LoadOptions& options) {
  const std::string bytes = readWholeFile(file, options.max_points * 16);
  constexpr std::size_t kRecord = 4 * sizeof(float);
  if (bytes.size() % kRecord != 0)
    throw ScanError(file, "truncated: " + std::to_string(bytes.size()) +
                              " bytes is not a whole number of 16-byte KITTI points");
  const std::size_t count = bytes.size() / kRecord;
  Scan scan;
  scan.points.reserve(count);
  scan.status.reserve(count);
  scan.intensity.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    float record[4];
    std::memcpy(record, bytes.data() + i * kRecord, kRecord);
    appendPoint(scan, record[0], record[1], record[2]);
    scan.intensity[i] = record[3];
  }
  scan.metadata.format = "kitti bin";
  scan.metadata.frame = "as stored: metres, x forward, z up";
  return scan;
}

}  // namespace clearway::detail
