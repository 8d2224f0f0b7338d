#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>

#include "clearway/io/file_util.h"
#include "clearway/io/scan_io.h"
#include "clearway/io/scan_lines.h"
#include "readers.h"

namespace clearway {
namespace detail {

std::string readFilePrefix(const std::filesystem::path& file, std::size_t max_bytes,
                           std::uintmax_t& file_size) {
  requireRegularFile(file);
  std::error_code error;
  file_size = std::filesystem::file_size(file, error);
  if (error) throw ScanError(file, "cannot read its size: " + error.message());
  if (file_size == 0) throw ScanError(file, "empty file");
  std::ifstream stream(file, std::ios::binary);
  if (!stream) throw ScanError(file, "cannot open for reading (permissions?)");
  std::string prefix(std::min<std::uintmax_t>(max_bytes, file_size), '\0');
  stream.read(prefix.data(), static_cast<std::streamsize>(prefix.size()));
  prefix.resize(static_cast<std::size_t>(stream.gcount()));
  return prefix;
}

void addCaution(Scan& scan, const std::string& caution) {
  std::string& all = scan.metadata.caution;
  all += (all.empty() ? "" : "; ") + caution;
}

namespace {

// The memory the machine has available now (/proc/meminfo's MemAvailable) [bytes]; 0 where it
// cannot be read.
std::uint64_t availableMemory() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key, unit;
  std::uint64_t kibibytes = 0;
  while (meminfo >> key >> kibibytes) {
    if (key == "MemAvailable:") return kibibytes * 1024;
    std::getline(meminfo, unit);  // the rest of the line: its unit
  }
  return 0;
}

std::string memoryText(std::uint64_t bytes) {
  char text[32];
  if (bytes < 1'000'000'000)
    std::snprintf(text, sizeof text, "%.0f MB", double(bytes) / 1e6);
  else
    std::snprintf(text, sizeof text, "%.1f GB", double(bytes) / 1e9);
  return text;
}

}  // namespace

void refuseBeyondMemory(const std::filesystem::path& file, std::uint64_t points,
                        std::uint64_t file_bytes, const LoadOptions& options) {
  const std::uint64_t budget =
      options.memory_budget > 0 ? options.memory_budget : availableMemory();
  if (budget == 0) return;
  const std::uint64_t needed = file_bytes + points * kBytesPerPointToSegment;
  if (needed <= budget) return;
  throw ScanError(file, std::to_string(points) +
                            " points: loading and segmenting them takes about " +
                            memoryText(needed) + ", and " + memoryText(budget) +
                            " is available (thin the scan, or free memory)");
}

void appendPoint(Scan& scan, float x, float y, float z) {
  scan.points.push_back({x, y, z});
  const bool finite = std::isfinite(x) && std::isfinite(y) && std::isfinite(z);
  scan.status.push_back(finite ? PointStatus::kValid : PointStatus::kNoReturn);
}

}  // namespace detail

namespace {

// The farthest-reaching terrestrial laser scanners measure about 6 km; no robot's sensor returns a
// point farther than this from itself [m]. Random bytes read as floats mostly are (any bit pattern
// is some float, most of them huge), and so is a georeferenced cloud, whose float coordinates are
// too coarse there for a 5 cm map anyway.
constexpr double kFarthestPossibleReturn = 10'000.0;

// Points lie in the sensor's frame (sensor_pose maps them to the world), so a point's distance from
// the origin is its range. A few absurd ranges are corrupt records and become no-returns, said as
// such; more than a few mean the body is not measurements at all, and the file is refused.
void refuseOrDropImpossibleRanges(Scan& scan, const std::filesystem::path& file) {
  constexpr double kFarthestSquared = kFarthestPossibleReturn * kFarthestPossibleReturn;
  std::size_t impossible = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!scan.isValid(i)) continue;
    const Point3f& p = scan.points[i];
    if (double(p.x) * p.x + double(p.y) * p.y + double(p.z) * p.z <= kFarthestSquared) continue;
    scan.status[i] = PointStatus::kNoReturn;
    ++impossible;
  }
  if (impossible == 0) return;
  const std::string counted = std::to_string(impossible) + " of " + std::to_string(scan.size()) +
                              " points lie over 10 km from the sensor";
  if (double(impossible) > detail::kMostImplausiblePointShare * double(scan.size()))
    throw ScanError(file, "its points are not range measurements: " + counted +
                              ", farther than any scanner measures (is the body corrupt, its DATA "
                              "type or byte order wrong, or its unit not metres? a georeferenced "
                              "cloud must first be moved to its sensor's origin)");
  detail::addCaution(scan, counted + " and were read as no returns (corrupt records)");
}

// Valid points all within this of one another [m] are one place seen again and again, not a scan.
constexpr double kOnePlace = 1e-3;

// A file whose points all lie at one place (a converter writing one point over and over, a
// frame of zeros with a few corrupt records) holds nothing to segment; its reason was "the scan
// has one scan line: give its rings", which sent the operator to the wrong problem.
void refusePointsAllAtOnePlace(const Scan& scan, const std::filesystem::path& file) {
  Eigen::AlignedBox3d box;
  for (std::size_t i = 0; i < scan.size(); ++i)
    if (scan.isValid(i))
      box.extend(Eigen::Vector3d(scan.points[i].x, scan.points[i].y, scan.points[i].z));
  // One point is a scan too sparse to segment, which the pipeline says.
  if (scan.validCount() < 2 || box.diagonal().norm() > kOnePlace) return;
  const Eigen::Vector3d at = box.center();
  char place[96];
  std::snprintf(place, sizeof place, "(%.3f, %.3f, %.3f)", at.x(), at.y(), at.z());
  throw ScanError(file, "all " + std::to_string(scan.validCount()) +
                            " valid points lie at one place, " + place +
                            ": nothing was scanned (a converter writing one point again?)");
}

}  // namespace

ScanFormat formatFromPath(const std::filesystem::path& file) {
  std::string extension = file.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (extension == ".pcd") return ScanFormat::kPcd;
  if (extension == ".ply") return ScanFormat::kPly;
  if (extension == ".xyz" || extension == ".txt" || extension == ".dat" || extension == ".asc")
    return ScanFormat::kXyz;
  if (extension == ".bin") return ScanFormat::kKittiBin;
  if (extension == ".3d") return ScanFormat::kUos;
  throw ScanError(file, "unknown extension '" + extension +
                            "' (known: .pcd .ply .xyz .txt .dat .asc .bin .3d)");
}

bool looksLikeScanFile(const std::filesystem::path& file) {
  ScanFormat format;
  try {
    format = formatFromPath(file);
  } catch (const ScanError&) {
    return false;
  }
  if (format != ScanFormat::kXyz) return true;
  try {
    return detail::checkTextScanStart(file) > 0;  // a header alone is a note, not a scan
  } catch (const ScanError&) {
    return false;
  }
}

std::string formatName(ScanFormat format) {
  switch (format) {
    case ScanFormat::kPcd:
      return "pcd";
    case ScanFormat::kPly:
      return "ply";
    case ScanFormat::kXyz:
      return "xyz";
    case ScanFormat::kKittiBin:
      return "kitti bin";
    case ScanFormat::kUos:
      return "3dtk uos";
  }
  return "unknown";
}

Scan loadScan(const std::filesystem::path& file, const LoadOptions& options) {
  // What the path is comes before what its name says: a folder is no "unknown extension ''".
  requireRegularFile(file);
  const ScanFormat format = formatFromPath(file);
  reportProgress(options.progress, 0.0);
  Scan scan;
  switch (format) {
    case ScanFormat::kPcd:
      scan = detail::readPcd(file, options);
      break;
    case ScanFormat::kPly:
      scan = detail::readPly(file, options);
      break;
    case ScanFormat::kXyz:
      scan = detail::readXyz(file, options);
      break;
    case ScanFormat::kKittiBin:
      scan = detail::readKittiBin(file, options);
      break;
    case ScanFormat::kUos:
      scan = detail::readUos(file, options);
      break;
  }
  if (scan.empty()) throw ScanError(file, "empty cloud: no points");
  scan.metadata.source_path = file.string();
  if (scan.sensor_pose) scan.pose_source = PoseSource::kFile;
  refuseOrDropImpossibleRanges(scan, file);

  if (format == ScanFormat::kUos) markSaturatedRange(scan);
  markSelfHits(scan, options.self_hit_radius);
  if (scan.validCount() == 0) {
    // Said by kind: a scan all at one range (the scanner's maximum, saturated) is not "no
    // returns".
    std::size_t by_kind[4] = {0, 0, 0, 0};
    for (const PointStatus status : scan.status)
      ++by_kind[std::min<std::size_t>(std::size_t(status), 3)];
    std::string kinds;
    const std::pair<PointStatus, const char*> names[] = {{PointStatus::kNoReturn, "no returns"},
                                                         {PointStatus::kMaxRange, "at max range"},
                                                         {PointStatus::kSelfHit, "self hits"}};
    for (const auto& [status, name] : names)
      if (const std::size_t count = by_kind[std::size_t(status)]; count > 0)
        kinds += (kinds.empty() ? "" : ", ") + std::to_string(count) + " " + name;
    throw ScanError(file, "no valid points: all " + std::to_string(scan.size()) + " are " + kinds);
  }
  refusePointsAllAtOnePlace(scan, file);
  if (scan.lines.empty()) {
    reconstructScanLines(scan, options.line_break_deg * std::numbers::pi / 180.0);
    if (options.rings == 0) recoverFiringOrderRings(scan);
  }
  if (options.rings > 0 && scan.lines.size() != options.rings) {
    const std::string why_not = recoverRings(scan, options.rings);
    if (!why_not.empty())
      throw ScanError(file, "--rings " + std::to_string(options.rings) + ": " + why_not);
  }
  checkScanInvariants(scan);
  reportProgress(options.progress, 1.0);
  return scan;
}

}  // namespace clearway
