#include "clearway/scan.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace clearway {

std::size_t Scan::validCount() const {
  return static_cast<std::size_t>(std::count(status.begin(), status.end(), PointStatus::kValid));
}

bool Scan::isOrganised() const {
  if (lines.size() < 2) return false;
  const std::size_t first_count = lines.front().count;
  return std::all_of(lines.begin(), lines.end(),
                     [first_count](const ScanLine& line) { return line.count == first_count; });
}

std::size_t Scan::pointsPerLine() const {
  std::size_t longest = 0;
  for (const ScanLine& line : lines)
    longest = std::max(longest, line.count);
  return longest;
}

std::span<const Point3f> Scan::linePoints(std::size_t line) const {
  const ScanLine& scan_line = lines.at(line);
  return std::span<const Point3f>(points).subspan(scan_line.first, scan_line.count);
}

Bounds validBounds(const Scan& scan) {
  Bounds bounds;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!scan.isValid(i)) continue;
    const Point3f& p = scan.points[i];
    bounds.min = {std::min(bounds.min.x, p.x), std::min(bounds.min.y, p.y),
                  std::min(bounds.min.z, p.z)};
    bounds.max = {std::max(bounds.max.x, p.x), std::max(bounds.max.y, p.y),
                  std::max(bounds.max.z, p.z)};
  }
  return bounds;
}

void checkScanInvariants(const Scan& scan) {
  const std::size_t n = scan.size();
  if (scan.status.size() != n) throw std::logic_error("scan: status size differs from points");
  if (!scan.intensity.empty() && scan.intensity.size() != n)
    throw std::logic_error("scan: intensity size differs from points");
  if (!scan.alpha.empty() && scan.alpha.size() != n)
    throw std::logic_error("scan: alpha size differs from points");
  std::size_t next = 0;
  for (const ScanLine& line : scan.lines) {
    if (line.first != next) throw std::logic_error("scan: lines do not cover the points in order");
    next += line.count;
  }
  if (next != n)
    throw std::logic_error("scan: lines cover " + std::to_string(next) + " of " +
                           std::to_string(n) + " points");
  for (std::size_t i = 0; i < n; ++i) {
    const Point3f& p = scan.points[i];
    if (scan.isValid(i) && !(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)))
      throw std::logic_error("scan: point " + std::to_string(i) + " is valid but not finite");
  }
}

std::size_t markSelfHits(Scan& scan, double radius) {
  const double radius_squared = radius * radius;
  std::size_t marked = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!scan.isValid(i)) continue;
    const Point3f& p = scan.points[i];
    const double range_squared = double(p.x) * p.x + double(p.y) * p.y + double(p.z) * p.z;
    if (range_squared < radius_squared) {
      scan.status[i] = PointStatus::kSelfHit;
      ++marked;
    }
  }
  return marked;
}

}  // namespace clearway
