// Plain ASCII point lists: XYZ/TXT/DAT ("x y z [intensity]", metres) and 3DTK's "uos" .3d
// (centimetres, left-handed, y up) with its .pose sidecar.

#include <cctype>
#include <charconv>
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

// A pose file holds six numbers; anything much larger is not one.
constexpr std::uintmax_t kMaxPoseBytes = 4096;
// How much of a text scan is looked at before the whole file is read.
constexpr std::size_t kSniffBytes = 64 * 1024;

// Parses the complete lines of the file's first bytes: garbage is refused (naming its line) before
// gigabytes of it are read. Returns the rows of numbers they hold.
std::size_t checkTextHead(const std::filesystem::path& file, std::string_view head,
                          std::uintmax_t file_size) {
  if (head.size() < file_size) {
    const std::size_t last_newline = head.rfind('\n');
    if (last_newline == std::string_view::npos)
      throw ScanError(file, "not a text point file: no line break in its first " +
                                std::to_string(head.size()) + " bytes");
    head = head.substr(0, last_newline + 1);
  }
  std::size_t rows = 0;
  parseNumberRows(file, head, {}, [&rows](const std::array<double, 4>&, std::size_t) { ++rows; },
                  {});
  return rows;
}

}  // namespace

std::size_t checkTextScanStart(const std::filesystem::path& file) {
  // Recognise the format from the first bytes before reading (and allocating for) the whole file.
  std::uintmax_t file_size = 0;
  const std::string head = readFilePrefix(file, kSniffBytes, file_size);
  if (head.find('\0') != std::string::npos)
    throw ScanError(file, "binary data in a text point file (wrong extension?)");
  if (file_size > kMaxAsciiBytes)
    throw ScanError(file, "file of " + std::to_string(file_size) +
                              " bytes is larger than the limit of " +
                              std::to_string(kMaxAsciiBytes) + " bytes");
  return checkTextHead(file, head, file_size);
}

namespace {

std::string readAsciiScan(const std::filesystem::path& file) {
  checkTextScanStart(file);
  std::string text = readWholeFile(file, kMaxAsciiBytes);
  if (text.find('\0') != std::string::npos)
    throw ScanError(file, "binary data in a text point file (wrong extension?)");
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

// The .pose sidecar is optional, but one that is there must be read: a silently ignored pose puts
// the scan in the wrong place.
std::optional<SensorPose> readUosPose(const std::filesystem::path& scan_file) {
  std::filesystem::path pose_file = scan_file;
  pose_file.replace_extension(".pose");
  std::error_code error;
  if (!std::filesystem::exists(std::filesystem::symlink_status(pose_file, error)))
    return std::nullopt;
  const std::string text = readWholeFile(pose_file, kMaxPoseBytes);
  std::array<double, 6> values{};
  std::size_t count = 0;
  const char* at = text.data();
  const char* end = text.data() + text.size();
  // A UTF-8 byte-order mark (editors on Windows write one) is no number, and invisible in the
  // message that said so ("found '0'"): skipped, as in the scans' own text.
  if (std::string_view(text).starts_with(kByteOrderMark)) at += kByteOrderMark.size();
  while (true) {
    while (at < end && std::isspace(static_cast<unsigned char>(*at)))
      ++at;
    if (at == end) break;
    const char* word_end = at;
    while (word_end < end && !std::isspace(static_cast<unsigned char>(*word_end)))
      ++word_end;
    double value = 0.0;
    const auto [parsed, failure] = std::from_chars(at, word_end, value);
    if (failure != std::errc() || parsed != word_end || !std::isfinite(value))
      throw ScanError(pose_file, "expected six finite numbers 'tx ty tz' and 'rx ry rz', found '" +
                                     std::string(at, std::min<std::size_t>(40, word_end - at)) +
                                     "'");
    if (count >= 6)  // a seventh number: how many is the problem, not which
      throw ScanError(pose_file,
                      "expected six numbers 'tx ty tz' and 'rx ry rz', found more than six");
    values[count++] = value;
    at = word_end;
  }
  if (count != 6)
    throw ScanError(pose_file, "expected six numbers 'tx ty tz' and 'rx ry rz', found " +
                                   std::to_string(count));
  return uosPoseToClearway(values);
}

// Text rows "x y z [intensity]", each turned into Clearway's frame by `convert`.
Scan readTextPoints(const std::filesystem::path& file, const LoadOptions& options,
                    Point3f (*convert)(const std::array<double, 4>&)) {
  const std::string text = readAsciiScan(file);
  Scan scan;
  bool has_intensity = false;
  parseNumberRows(
      file, text, {},
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

// A Velodyne sees at most about 120 m; a return farther than this is no measurement [m].
constexpr double kFarthestVelodyneReturn = 1000.0;
// Nor is one nearer than this, unless it is exactly at the origin (a no-return some converters
// write as zeros): text read as floats gives ranges of 1e-5 m and less [m].
constexpr double kNearestVelodyneReturn = 1e-3;

// A record that no Velodyne frame holds: a coordinate not finite, a range over 1 km or under
// 1 mm (but for zeros), a reflectance that is not a finite number of at least 0. Records of
// another layout (x y z alone, or five floats) read as 16-byte ones put coordinates, about half
// of them negative, where the reflectance belongs.
bool implausibleVelodyneRecord(const float (&record)[4], double range) {
  const bool at_origin = record[0] == 0.0F && record[1] == 0.0F && record[2] == 0.0F;
  return !(range <= kFarthestVelodyneReturn) || (!at_origin && range < kNearestVelodyneReturn) ||
         !(record[3] >= 0.0F) || !std::isfinite(record[3]);
}

Scan readKittiBin(const std::filesystem::path& file, const LoadOptions& options) {
  std::error_code size_error;  // an unreadable file is readWholeFile's to say
  if (const std::uintmax_t size = std::filesystem::file_size(file, size_error); !size_error)
    refuseBeyondMemory(file, size / 16, size, options);
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
  std::size_t implausible = 0;
  for (std::size_t i = 0; i < count; ++i) {
    float record[4];
    std::memcpy(record, bytes.data() + i * kRecord, kRecord);
    appendPoint(scan, record[0], record[1], record[2]);
    scan.intensity[i] = record[3];
    const double range = std::sqrt(double(record[0]) * record[0] + double(record[1]) * record[1] +
                                   double(record[2]) * record[2]);
    implausible += implausibleVelodyneRecord(record, range);
    // The frame is the sensor's own: a return over 1 km away is a corrupt record, not a point (a
    // few at 1e30 m broke the rings' recovery and took two thirds of a frame's green cells).
    if (!(range <= kFarthestVelodyneReturn)) scan.status.back() = PointStatus::kNoReturn;
  }
  // The format has no header to check: a file of other bytes would load as meaningless points.
  // Its floats are then mostly absurd (any bit pattern is some float), a real frame's never are.
  if (double(implausible) > kMostImplausiblePointShare * double(count))
    throw ScanError(file, "not a Velodyne frame: " + std::to_string(implausible) + " of " +
                              std::to_string(count) +
                              " records are not finite, lie over 1 km away or within 1 mm, or "
                              "have a negative reflectance (a KITTI .bin holds x, y, z and "
                              "reflectance as 32-bit floats, 16 bytes a point)");
  scan.metadata.format = "kitti bin";
  scan.metadata.frame = "as stored: metres, x forward, z up";
  // The format's frame is the Velodyne's on the car, z up by KITTI's definition (the car stands on
  // the road it scans): that is the frame's pose, as a 3DTK .pose file gives one.
  scan.sensor_pose = SensorPose{};
  return scan;
}

}  // namespace clearway::detail
