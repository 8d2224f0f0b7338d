#include "ring_support.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "parallel.h"

namespace clearway::detail {
namespace {

// Returns of neighbouring rings face each other within this many azimuth steps: the lasers of a
// multi-beam head fire a little apart in azimuth, and a return may be missing.
constexpr double kFacingSteps = 3.0;

// A segment is walked in steps of this share of a cell, so that no cell it crosses is skipped.
constexpr double kWalkStepCells = 0.5;

// The insertion sort of a ring gives way to a full sort beyond this many moves per return.
constexpr std::size_t kInsertionMovesPerReturn = 8;

struct RingEntry {
  float azimuth;
  std::uint32_t point;
};

// A ring's valid returns in order of azimuth.
std::vector<RingEntry> byAzimuth(const Scan& scan, const ScanLine& line) {
  std::vector<RingEntry> entries;
  entries.reserve(line.count);
  for (std::size_t i = line.first; i < line.first + line.count; ++i)
    if (scan.isValid(i))
      entries.push_back({std::atan2(scan.points[i].y, scan.points[i].x), std::uint32_t(i)});
  // A ring is usually stored in the order it was swept, one way round from some azimuth, with a
  // little jitter: reversed when it turns clockwise and rotated to start at its smallest azimuth,
  // an insertion sort puts it in order at a few moves a return. Otherwise a full sort.
  auto before = [](const RingEntry& a, const RingEntry& b) { return a.azimuth < b.azimuth; };
  std::size_t descents = 0;
  for (std::size_t i = 1; i < entries.size(); ++i)
    descents += entries[i].azimuth < entries[i - 1].azimuth;
  if (2 * descents > entries.size()) std::reverse(entries.begin(), entries.end());
  const auto smallest = std::min_element(entries.begin(), entries.end(), before);
  std::rotate(entries.begin(), smallest, entries.end());
  std::size_t moves = 0;
  const std::size_t budget = kInsertionMovesPerReturn * entries.size();
  for (std::size_t i = 1; i < entries.size() && moves <= budget; ++i)
    for (std::size_t j = i; j > 0 && before(entries[j], entries[j - 1]) && moves <= budget; --j) {
      std::swap(entries[j], entries[j - 1]);
      ++moves;
    }
  if (moves > budget) std::sort(entries.begin(), entries.end(), before);
  return entries;
}

double azimuthGap(double a, double b) {
  const double gap = std::abs(a - b);
  return std::min(gap, 2.0 * std::numbers::pi - gap);
}

}  // namespace

RingLayout ringLayout(const Scan& scan, const std::vector<std::size_t>& rings_by_elevation,
                      double azimuth_step, int threads) {
  RingLayout layout;
  if (rings_by_elevation.size() < 2 || !(azimuth_step > 0.0)) return layout;
  const double tolerance = kFacingSteps * azimuth_step;
  std::vector<std::vector<RingEntry>> rings(rings_by_elevation.size());
  parallelChunks(rings.size(), threads, [&](std::size_t begin, std::size_t end, std::size_t) {
    for (std::size_t rank = begin; rank < end; ++rank)
      rings[rank] = byAzimuth(scan, scan.lines[rings_by_elevation[rank]]);
  });
  layout.facing.assign(scan.size(), RingLayout::kNone);
  parallelChunks(rings.size() - 1, threads, [&](std::size_t begin, std::size_t end, std::size_t) {
    for (std::size_t rank = begin; rank < end; ++rank) {
      const std::vector<RingEntry>& above = rings[rank + 1];
      if (above.empty()) continue;
      // Both rings in order of azimuth: the return above nearest to each one is found by walking
      // along (either side of it, or across the wrap at +-pi).
      std::size_t next = 0;
      for (const RingEntry& entry : rings[rank]) {
        while (next < above.size() && above[next].azimuth < entry.azimuth)
          ++next;
        const RingEntry* candidates[] = {next < above.size() ? &above[next] : &above.front(),
                                         next > 0 ? &above[next - 1] : &above.back()};
        const RingEntry* facing = nullptr;
        double best = tolerance;
        for (const RingEntry* candidate : candidates) {
          const double gap = azimuthGap(entry.azimuth, candidate->azimuth);
          if (gap <= best) {
            best = gap;
            facing = candidate;
          }
        }
        if (facing) layout.facing[entry.point] = facing->point;
      }
    }
  });
  return layout;
}

void supportBetweenRings(const Scan& scan, const RingLayout& layout, double min_gap, double max_gap,
                         const Plane& plane, double tolerance, double per_metre,
                         const std::vector<std::uint32_t>& support,
                         const std::vector<Eigen::Vector2d>& uv, const SupportFrame& frame,
                         cv::Mat& counts, int min_count) {
  if (layout.empty()) return;
  const double min_gap_squared = min_gap * min_gap, max_gap_squared = max_gap * max_gap;
  const Eigen::Vector3f normal = plane.normal.cast<float>();
  const auto offset = float(plane.offset), flat_band = float(tolerance);
  const auto widening = float(per_metre);
  auto cellOf = [&](const Eigen::Vector2d& q) {
    return Eigen::Vector2i(int(std::floor((q.x() - frame.uv0.x()) / frame.cell)),
                           int(std::floor((q.y() - frame.uv0.y()) / frame.cell)));
  };
  const auto min_value = std::uint16_t(min_count);
  for (std::size_t k = 0; k < support.size(); ++k) {
    const std::uint32_t other = layout.facing[support[k]];
    if (other == RingLayout::kNone) continue;
    const Point3f& a = scan.points[support[k]];
    const Point3f& p = scan.points[other];
    const double dx = double(a.x) - p.x, dy = double(a.y) - p.y, dz = double(a.z) - p.z;
    const double gap_squared = dx * dx + dy * dy + dz * dz;
    if (gap_squared <= min_gap_squared || gap_squared > max_gap_squared) continue;
    const Eigen::Vector3f q(p.x, p.y, p.z);
    if (std::abs(normal.dot(q) - offset) > flat_band + widening * q.norm()) continue;
    const Eigen::Vector3d relative = q.cast<double>() - frame.centre;
    const Eigen::Vector2d& from = uv[k];
    const Eigen::Vector2d to(relative.dot(frame.u_axis), relative.dot(frame.v_axis));
    // Returns in the same or neighbouring cells leave no cell between them.
    if ((cellOf(from) - cellOf(to)).cwiseAbs().maxCoeff() <= 1) continue;
    const int steps =
        std::max(1, int(std::ceil((to - from).norm() / (kWalkStepCells * frame.cell))));
    for (int s = 1; s < steps; ++s) {
      const Eigen::Vector2i c = cellOf(from + (to - from) * (double(s) / steps));
      if (c.x() < 0 || c.y() < 0 || c.x() >= counts.cols || c.y() >= counts.rows) continue;
      std::uint16_t& count = counts.ptr<std::uint16_t>(c.y())[c.x()];
      count = std::max(count, min_value);
    }
  }
}

}  // namespace clearway::detail
