#include "clearway/io/scan_lines.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <type_traits>
#include <vector>

namespace clearway {
namespace {

constexpr double kPi = std::numbers::pi;

double wrapAngle(double angle) {
  while (angle > kPi)
    angle -= 2.0 * kPi;
  while (angle < -kPi)
    angle += 2.0 * kPi;
  return angle;
}

struct Direction {
  double azimuth;
  double elevation;
};

Direction directionOf(const Point3f& p) {
  const double horizontal = std::hypot(double(p.x), double(p.y));
  return {std::atan2(double(p.y), double(p.x)), std::atan2(double(p.z), horizontal)};
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// A step is "normal" along a line; a jump this large in any direction is never within one line.
constexpr double kHalfTurnJump = 150.0 * kPi / 180.0;
// One turn of the azimuth: no line of any sensor sweeps more.
constexpr double kFullTurn = 2.0 * kPi;

// Puts the points in `order` (a permutation) and keeps status, intensity and alpha with them.
void reorderPoints(Scan& scan, const std::vector<std::size_t>& order) {
  auto apply = [&](auto& values) {
    if (values.empty()) return;
    std::remove_reference_t<decltype(values)> sorted;
    sorted.reserve(values.size());
    for (std::size_t i : order)
      sorted.push_back(values[i]);
    values = std::move(sorted);
  };
  apply(scan.points);
  apply(scan.status);
  apply(scan.intensity);
  apply(scan.alpha);
}

}  // namespace

void reconstructScanLines(Scan& scan, double break_angle_rad) {
  scan.lines.clear();
  if (scan.empty()) return;

  // Steps in azimuth and elevation between consecutive points that have a direction. Self hits
  // and saturated ranges do: the beam still went that way. Only no-returns and points at the
  // origin itself carry none.
  std::vector<std::size_t> valid_indices;
  valid_indices.reserve(scan.size());
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const Point3f& p = scan.points[i];
    const double range_squared = double(p.x) * p.x + double(p.y) * p.y + double(p.z) * p.z;
    if (scan.status[i] != PointStatus::kNoReturn && range_squared > 1e-6)
      valid_indices.push_back(i);
  }

  std::vector<double> azimuth_steps;
  std::vector<double> elevation_steps;
  azimuth_steps.reserve(valid_indices.size());
  elevation_steps.reserve(valid_indices.size());
  std::vector<Direction> directions(valid_indices.size());
  for (std::size_t k = 0; k < valid_indices.size(); ++k) {
    directions[k] = directionOf(scan.points[valid_indices[k]]);
    if (k == 0) continue;
    azimuth_steps.push_back(wrapAngle(directions[k].azimuth - directions[k - 1].azimuth));
    elevation_steps.push_back(directions[k].elevation - directions[k - 1].elevation);
  }

  auto absolute = [](std::vector<double> steps) {
    for (double& step : steps)
      step = std::abs(step);
    return steps;
  };
  const double azimuth_motion = median(absolute(azimuth_steps));
  const double elevation_motion = median(absolute(elevation_steps));
  const bool along_elevation = elevation_motion > azimuth_motion;
  const std::vector<double>& steps = along_elevation ? elevation_steps : azimuth_steps;
  const double typical_step = median(steps);

  if (valid_indices.size() < 3 || typical_step == 0.0) {
    scan.lines.push_back({0, scan.size()});
    return;
  }
  const double forward = typical_step > 0.0 ? 1.0 : -1.0;

  std::size_t line_start = 0;
  // Azimuth swept since the line began: a multi-beam ring (KITTI keeps ring after ring) ends where
  // the azimuth has gone once around, with no jump back to see, since the wrap is a small step.
  double swept = 0.0;
  for (std::size_t k = 1; k < valid_indices.size(); ++k) {
    const double step = steps[k - 1] * forward;
    swept += step;
    // Half a step short of the turn: the next ring starts where this one did.
    const bool full_turn = !along_elevation && swept >= kFullTurn - 0.5 * std::abs(typical_step);
    const bool jumps_back = step < -break_angle_rad || std::abs(step) > kHalfTurnJump || full_turn;
    if (!jumps_back) continue;
    swept = 0.0;
    // No-returns between the two points cannot tell which line they belong to; they open the
    // new line, as scanners that report every beam start a line with the first beam.
    const std::size_t split = std::max(valid_indices[k - 1] + 1, line_start + 1);
    scan.lines.push_back({line_start, split - line_start});
    line_start = split;
  }
  scan.lines.push_back({line_start, scan.size() - line_start});
}

void groupIntoRings(Scan& scan, const std::vector<int>& ring_of) {
  if (ring_of.size() != scan.size() || scan.empty()) return;
  std::vector<std::size_t> order(scan.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    order[i] = i;
  // Stable: a driver writes each ring in azimuth order, which is kept.
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return ring_of[a] < ring_of[b]; });
  std::vector<int> rings_sorted(order.size());
  for (std::size_t k = 0; k < order.size(); ++k)
    rings_sorted[k] = ring_of[order[k]];
  reorderPoints(scan, order);
  scan.lines.clear();
  std::size_t start = 0;
  for (std::size_t k = 1; k <= rings_sorted.size(); ++k)
    if (k == rings_sorted.size() || rings_sorted[k] != rings_sorted[start]) {
      scan.lines.push_back({start, k - start});
      start = k;
    }
}

// With this many rings or more, one holding most returns means the recovery failed.
constexpr std::size_t kFewestRingsJudged = 3;

std::string recoverRings(Scan& scan, std::size_t rings) {
  if (rings == 0 || scan.empty()) return {};
  // Elevation and azimuth of each point with a direction; no-returns go to the ring before them.
  std::vector<double> elevation(scan.size(), std::numeric_limits<double>::quiet_NaN());
  std::vector<double> azimuth(scan.size(), 0.0);
  std::vector<double> sorted;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const Point3f& p = scan.points[i];
    const double horizontal = std::hypot(double(p.x), double(p.y));
    if (scan.status[i] == PointStatus::kNoReturn || horizontal + std::abs(p.z) <= 1e-6) continue;
    elevation[i] = std::atan2(double(p.z), horizontal);
    azimuth[i] = std::atan2(double(p.y), double(p.x));
    sorted.push_back(elevation[i]);
  }
  if (sorted.size() < rings) return {};
  std::sort(sorted.begin(), sorted.end());
  // The rings are the clusters of elevation: cut at the rings - 1 widest gaps.
  std::vector<std::size_t> gap_order(sorted.size() - 1);
  for (std::size_t k = 0; k < gap_order.size(); ++k)
    gap_order[k] = k;
  const std::size_t cuts = std::min(rings - 1, gap_order.size());
  std::partial_sort(gap_order.begin(), gap_order.begin() + std::ptrdiff_t(cuts), gap_order.end(),
                    [&](std::size_t a, std::size_t b) {
                      return sorted[a + 1] - sorted[a] > sorted[b + 1] - sorted[b];
                    });
  std::vector<double> bounds;  // elevation midway across each cut
  for (std::size_t k = 0; k < cuts; ++k)
    bounds.push_back(0.5 * (sorted[gap_order[k]] + sorted[gap_order[k] + 1]));
  std::sort(bounds.begin(), bounds.end());
  std::vector<int> ring_of(scan.size(), 0);
  int last_ring = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (std::isnan(elevation[i])) {
      ring_of[i] = last_ring;
      continue;
    }
    last_ring = int(std::upper_bound(bounds.begin(), bounds.end(), elevation[i]) - bounds.begin());
    ring_of[i] = last_ring;
  }
  // Seen from one point, the rings of a head whose lasers sit apart overlap in elevation (KITTI's
  // HDL-64E: every pair of neighbours): the widest gaps then fall among a few stray returns, and
  // one band takes nearly all of them. That is no recovery: say so rather than go on with it.
  std::vector<std::size_t> per_ring(cuts + 1, 0);
  for (std::size_t i = 0; i < scan.size(); ++i)
    if (!std::isnan(elevation[i])) ++per_ring[std::size_t(ring_of[i])];
  const std::size_t fullest = *std::max_element(per_ring.begin(), per_ring.end());
  if (rings >= kFewestRingsJudged && 2 * fullest > sorted.size())
    return "the elevation angles do not fall into " + std::to_string(rings) +
           " rings: one band holds " + std::to_string(fullest) + " of " +
           std::to_string(sorted.size()) +
           " returns (a multi-beam head's lasers sit apart on it, so its rings overlap in "
           "elevation seen from one point); give the frame in its rings' order, one ring after "
           "another (then --rings is not needed), or with a PCD ring field";
  // Within a ring, points go in azimuth order (a ring is one turn of the head).
  std::vector<std::size_t> order(scan.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (ring_of[a] != ring_of[b]) return ring_of[a] < ring_of[b];
    return azimuth[a] < azimuth[b];
  });
  std::vector<int> sorted_rings(order.size());
  for (std::size_t k = 0; k < order.size(); ++k)
    sorted_rings[k] = ring_of[order[k]];
  reorderPoints(scan, order);
  scan.lines.clear();
  std::size_t start = 0;
  for (std::size_t k = 1; k <= sorted_rings.size(); ++k)
    if (k == sorted_rings.size() || sorted_rings[k] != sorted_rings[start]) {
      scan.lines.push_back({start, k - start});
      start = k;
    }
  return {};
}

std::size_t markSaturatedRange(Scan& scan, double min_fraction) {
  std::vector<double> ranges(scan.size(), 0.0);
  double largest = 0.0;
  std::size_t valid = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!scan.isValid(i)) continue;
    const Point3f& p = scan.points[i];
    ranges[i] = std::sqrt(double(p.x) * p.x + double(p.y) * p.y + double(p.z) * p.z);
    largest = std::max(largest, ranges[i]);
    ++valid;
  }
  if (valid == 0) return 0;
  // Saturated returns agree to the centimetre (3DTK: 32.758 .. 32.767 m); real far walls do not.
  const double threshold = largest * 0.999;
  std::size_t saturated = 0;
  for (std::size_t i = 0; i < scan.size(); ++i)
    if (scan.isValid(i) && ranges[i] >= threshold) ++saturated;
  // A handful of far points is a far wall, not a sensor artefact.
  constexpr std::size_t kMinSaturated = 10;
  if (saturated < kMinSaturated || double(saturated) < min_fraction * double(valid)) return 0;
  for (std::size_t i = 0; i < scan.size(); ++i)
    if (scan.isValid(i) && ranges[i] >= threshold) scan.status[i] = PointStatus::kMaxRange;
  return saturated;
}

}  // namespace clearway
