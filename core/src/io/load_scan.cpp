#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <numbers>

#include "clearway/io/scan_io.h"
#include "clearway/io/scan_lines.h"
#include "readers.h"

namespace clearway {
namespace detail {

void checkIsAScanFile(const std::filesystem::path& file) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(file, error);
  // A symbolic link loop or a folder without permission is not "no such file".
  if (error && error != std::errc::no_such_file_or_directory)
    throw ScanError(file, "cannot reach it: " + error.message());
  if (!std::filesystem::exists(status)) throw ScanError(file, "no such file");
  if (std::filesystem::is_directory(status))
    throw ScanError(file, "is a directory, not a scan file");
  if (!std::filesystem::is_regular_file(status))
    throw ScanError(file, "not a regular file (a device, a pipe or a socket), not a scan file");
}

std::string readFilePrefix(const std::filesystem::path& file, std::size_t max_bytes,
                           std::uintmax_t& file_size) {
  checkIsAScanFile(file);
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

void appendPoint(Scan& scan, float x, float y, float z) {
  scan.points.push_back({x, y, z});
  const bool finite = std::isfinite(x) && std::isfinite(y) && std::isfinite(z);
  scan.status.push_back(finite ? PointStatus::kValid : PointStatus::kNoReturn);
}

}  // namespace detail

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
  detail::checkIsAScanFile(file);
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
