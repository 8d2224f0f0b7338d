#include "clearway/io/scan_lines.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "readers.h"

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

// No-returns and points at the origin itself carry no direction.
bool hasDirection(const Scan& scan, std::size_t i) {
  const Point3f& p = scan.points[i];
  return scan.status[i] != PointStatus::kNoReturn &&
         std::hypot(double(p.x), double(p.y)) + std::abs(double(p.z)) > 1e-6;
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

// Puts the points in rings (`ring_of`, per point), the rings in increasing number, each in the
// order the file keeps it or, with `azimuth` (per point), in azimuth order; one line per ring.
void putInRings(Scan& scan, const std::vector<int>& ring_of, const std::vector<double>& azimuth) {
  std::vector<std::size_t> order(scan.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (ring_of[a] != ring_of[b] || azimuth.empty()) return ring_of[a] < ring_of[b];
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

// Ring numbers are in elevation order when, taken in that order, the rings' elevations travel no
// more than this many times the way from the lowest to the highest (small swaps of neighbours).
constexpr double kMostElevationTravel = 1.5;

std::string groupIntoRings(Scan& scan, const std::vector<double>& ring_numbers) {
  if (ring_numbers.size() != scan.size() || scan.empty()) return {};
  // Ring fields are 8- or 16-bit unsigned in every driver's output.
  constexpr double kHighestRingNumber = 65535.0;
  for (std::size_t i = 0; i < ring_numbers.size(); ++i) {
    const double value = ring_numbers[i];
    if (!(value >= 0.0 && value <= kHighestRingNumber && value == std::floor(value)))
      return "point " + std::to_string(i) + "'s ring number " + std::to_string(value) +
             " is not a whole number from 0 to 65535";
  }
  // Neighbouring lines must be neighbouring rings: the ground is triangulated and planes are
  // grown between them. A ROS driver numbers its rings by elevation (its lasers' calibrated
  // angles), but VeloView's laser_id is the firing order (a VLP-16's laser 0 looks 15 deg down,
  // laser 1 one up, laser 2 13 down): numbers that jump to and fro in elevation are replaced by
  // the order of the rings' median elevation, lowest first. A driver writes each ring in
  // azimuth order, which is kept.
  std::vector<int> ring_of(ring_numbers.begin(), ring_numbers.end());
  std::vector<std::vector<double>> elevations(
      std::size_t(*std::max_element(ring_of.begin(), ring_of.end())) + 1);
  std::vector<bool> present(elevations.size(), false);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    present[std::size_t(ring_of[i])] = true;
    if (hasDirection(scan, i))
      elevations[std::size_t(ring_of[i])].push_back(directionOf(scan.points[i]).elevation);
  }
  std::vector<std::pair<double, int>> by_elevation;  // (median elevation, ring number)
  for (std::size_t ring = 0; ring < elevations.size(); ++ring)
    if (present[ring])
      by_elevation.emplace_back(elevations[ring].empty() ? std::numeric_limits<double>::infinity()
                                                         : median(std::move(elevations[ring])),
                                int(ring));
  // In number order the elevations run up (or down) with small swaps at most: seen from one
  // point, an HDL-64E's neighbouring lasers, which sit apart on the head, can trade places, and
  // their numbers are the true order. Jumping to and fro they travel much farther than from the
  // lowest to the highest ring.
  double travelled = 0.0, lowest = std::numeric_limits<double>::infinity(),
         highest = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < by_elevation.size(); ++k) {
    const double elevation = by_elevation[k].first;
    if (!std::isfinite(elevation)) continue;
    lowest = std::min(lowest, elevation);
    highest = std::max(highest, elevation);
    if (k > 0 && std::isfinite(by_elevation[k - 1].first))
      travelled += std::abs(elevation - by_elevation[k - 1].first);
  }
  if (travelled > kMostElevationTravel * (highest - lowest))
    std::stable_sort(by_elevation.begin(), by_elevation.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<int> rank_of(elevations.size(), 0);
  for (std::size_t k = 0; k < by_elevation.size(); ++k)
    rank_of[std::size_t(by_elevation[k].second)] = int(k);
  for (int& ring : ring_of)
    ring = rank_of[std::size_t(ring)];
  putInRings(scan, ring_of, {});
  return {};
}

namespace {

// With this many rings or more, one holding most returns means the recovery failed.
constexpr std::size_t kFewestRingsJudged = 3;

// Each point's direction seen from the origin; NaN elevation for points without one (no-returns,
// points at the origin), which go to the ring of the point before them.
struct PointDirections {
  std::vector<double> elevation, azimuth;
  std::vector<double> sorted_elevations;  // of the points that have one
};

PointDirections pointDirections(const Scan& scan) {
  PointDirections d;
  d.elevation.assign(scan.size(), std::numeric_limits<double>::quiet_NaN());
  d.azimuth.assign(scan.size(), 0.0);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!hasDirection(scan, i)) continue;
    const Direction direction = directionOf(scan.points[i]);
    d.elevation[i] = direction.elevation;
    d.azimuth[i] = direction.azimuth;
    d.sorted_elevations.push_back(d.elevation[i]);
  }
  std::sort(d.sorted_elevations.begin(), d.sorted_elevations.end());
  return d;
}

// Puts each point in the ring whose elevation band holds it (`bounds`: the elevations between
// rings, increasing), the rings lowest first, each in azimuth order (a ring is one turn of the
// head). Returns why not, the scan unchanged, when one band takes most returns.
std::string splitIntoRings(Scan& scan, const PointDirections& d,
                           const std::vector<double>& bounds) {
  const std::size_t rings = bounds.size() + 1;
  std::vector<int> ring_of(scan.size(), 0);
  int last_ring = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (std::isnan(d.elevation[i])) {
      ring_of[i] = last_ring;
      continue;
    }
    last_ring =
        int(std::upper_bound(bounds.begin(), bounds.end(), d.elevation[i]) - bounds.begin());
    ring_of[i] = last_ring;
  }
  // Seen from one point, the rings of a head whose lasers sit apart overlap in elevation (KITTI's
  // HDL-64E: every pair of neighbours): the widest gaps then fall among a few stray returns, and
  // one band takes nearly all of them. That is no recovery: say so rather than go on with it.
  std::vector<std::size_t> per_ring(rings, 0);
  for (std::size_t i = 0; i < scan.size(); ++i)
    if (!std::isnan(d.elevation[i])) ++per_ring[std::size_t(ring_of[i])];
  const std::size_t fullest = *std::max_element(per_ring.begin(), per_ring.end());
  const std::size_t with_direction = d.sorted_elevations.size();
  if (rings >= kFewestRingsJudged && 2 * fullest > with_direction)
    return "the elevation angles do not fall into " + std::to_string(rings) +
           " rings: one band holds " + std::to_string(fullest) + " of " +
           std::to_string(with_direction) +
           " returns (a multi-beam head's lasers sit apart on it, so its rings overlap in "
           "elevation seen from one point); give the frame in its rings' order, one ring after "
           "another (then --rings is not needed), or with a PCD ring field";
  putInRings(scan, ring_of, d.azimuth);
  return {};
}

// A firing-order frame is told from a RoSi's vertical fans by its narrow field of view: multi-beam
// heads span 22.5 deg (Ouster OS2) to 45 deg (OS1) of elevation, a 2D scanner's fan 100 or 180 deg.
constexpr double kWidestMultiBeamView = 50.0 * kPi / 180.0;
// Heads have up to 128 lasers.
constexpr std::size_t kMostLasers = 128;
// Between neighbouring rings at least a third of a degree (an HDL-64E's upper block); within a
// ring of lasers that share one centre, the elevations agree to float rounding. A gap this wide
// in the sorted elevations separates two bands.
constexpr double kBandGap = 0.1 * kPi / 180.0;
// A band is a ring when it holds this share of the returns of an average ring or more (a top ring
// that sees mostly sky keeps a few returns; a stray return between rings is no ring).
constexpr double kSmallestRingShare = 0.05;
// Firing after firing, at most this share of the returns follow one of their own band in the
// file (a laser whose neighbour in the firing saw nothing, twice the same return).
constexpr double kMostSameBandSuccessors = 0.1;
// Successive pairs of returns looked at before the whole frame is.
constexpr std::size_t kQuickLook = 4096;

}  // namespace

std::string recoverRings(Scan& scan, std::size_t rings) {
  if (rings == 0 || scan.empty()) return {};
  const PointDirections d = pointDirections(scan);
  const std::vector<double>& sorted = d.sorted_elevations;
  if (sorted.size() < rings) return {};
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
  return splitIntoRings(scan, d, bounds);
}

std::size_t recoverFiringOrderRings(Scan& scan) {
  // A quick look first, as most frames are kept ring after ring or fan after fan: two successive
  // returns this close in elevation are in one band, and too many such pairs among the first
  // returns rule the frame out before every direction is computed.
  std::size_t looked = 0, close = 0;
  double previous = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t i = 0; i < scan.size() && looked < kQuickLook; ++i) {
    if (!hasDirection(scan, i)) continue;
    const double elevation = directionOf(scan.points[i]).elevation;
    if (!std::isnan(previous)) {
      ++looked;
      close += std::abs(elevation - previous) <= kBandGap;
    }
    previous = elevation;
  }
  if (double(close) > kMostSameBandSuccessors * double(looked)) return 0;

  const PointDirections d = pointDirections(scan);
  const std::vector<double>& sorted = d.sorted_elevations;
  if (sorted.size() < 2 * kMostLasers) return 0;
  // Robust field of view: the 1st to the 99th percentile of the elevations.
  const std::size_t percent = sorted.size() / 100;
  const double view = sorted[sorted.size() - 1 - percent] - sorted[percent];
  if (view > kWidestMultiBeamView) return 0;
  // From here on the frame zig-zags within a multi-beam head's view, as firings do: if its rings
  // cannot be told apart, the lines it keeps are not scan lines, and the user must know.
  auto cannotTellRingsApart = [&] {
    std::ostringstream caution;
    caution << "this looks like a multi-beam frame kept firing after firing (successive returns "
               "zig-zag within "
            << std::lround(view * 180.0 / kPi)
            << " deg of elevation), but its rings cannot be told apart by elevation (a head "
               "whose lasers sit apart, like an HDL-64E's, seen from one point): it is read as "
               "short vertical fans, which it is not; save it ring after ring or with a ring "
               "field";
    detail::addCaution(scan, caution.str());
    return std::size_t{0};
  };

  // Bands of elevation; the bounds between rings lie midway across the gaps beside them.
  struct Band {
    double low, high;
    std::size_t count;
  };
  std::vector<Band> bands{{sorted.front(), sorted.front(), 1}};
  for (std::size_t k = 1; k < sorted.size(); ++k) {
    if (sorted[k] - sorted[k - 1] > kBandGap) bands.push_back({sorted[k], sorted[k], 0});
    bands.back().high = sorted[k];
    ++bands.back().count;
  }
  const double average_band = double(sorted.size()) / double(bands.size());
  std::vector<Band> rings;
  for (const Band& band : bands)
    if (double(band.count) >= kSmallestRingShare * average_band) rings.push_back(band);
  if (rings.size() < 2 || rings.size() > kMostLasers) return cannotTellRingsApart();
  std::vector<double> bounds;
  for (std::size_t r = 1; r < rings.size(); ++r)
    bounds.push_back(0.5 * (rings[r - 1].high + rings[r].low));

  // Firing after firing, a return's successor in the file is another laser's, in another band.
  // Ring after ring (KITTI) it is in the same band, and so it is where the bands are rings run
  // together (lasers that sit apart on the head, seen from one point): no recovery then.
  std::size_t pairs = 0, same_band = 0;
  std::ptrdiff_t previous_band = -1;
  for (const double elevation : d.elevation) {
    if (std::isnan(elevation)) continue;
    const std::ptrdiff_t band =
        std::upper_bound(bounds.begin(), bounds.end(), elevation) - bounds.begin();
    if (previous_band >= 0) {
      ++pairs;
      same_band += band == previous_band;
    }
    previous_band = band;
  }
  if (double(same_band) > kMostSameBandSuccessors * double(pairs)) return cannotTellRingsApart();
  if (!splitIntoRings(scan, d, bounds).empty()) return cannotTellRingsApart();
  return rings.size();
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
