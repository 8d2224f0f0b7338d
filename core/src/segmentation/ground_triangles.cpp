// Ground triangles between neighbouring scan lines (docs/ALGORITHM.md, section 5): which lines,
// or fans within them, lie side by side, how their points pair up, and which triangles join ground.

#include "ground_triangles.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <optional>

#include "clearway/segmentation/scan_analysis.h"
#include "parallel.h"

namespace clearway::detail {
namespace {

constexpr double kPi = std::numbers::pi;
// A full turn closes over a gap between neighbouring lines of at most this many line steps, or
// kLargestSeamGap (lines lost at the start and end of the turn); the density check keeps such a
// wedge from showing green.
constexpr double kSeamSteps = 2.5;
constexpr double kLargestSeamGap = 15.0 * kPi / 180.0;

// Neighbouring lines are paired point by point: same index for organised scans, same relative
// position along the line for ragged ones.
std::size_t partner(const ScanLine& from, const ScanLine& to, std::size_t k) {
  if (from.count == to.count) return to.first + k;
  const std::size_t scaled = (k * to.count + from.count / 2) / std::max<std::size_t>(from.count, 1);
  return to.first + std::min(scaled, to.count - 1);
}

// Each ring's unwrapped azimuth starts where its first return points, in (-pi, pi]: a ring that
// starts just past the back (+179.9 deg) and its neighbour that starts just before it (-179.9 deg)
// would lie a whole turn apart, and no return of one would find its partner on the other. Each
// ring is moved by whole turns to start within half a turn of the ring before it.
void alignRingStarts(std::vector<double>& along, const std::vector<ScanLine>& rings) {
  const ScanLine* previous = nullptr;
  for (const ScanLine& ring : rings) {
    if (ring.count == 0) continue;
    if (previous) {
      const double start = along[ring.first];
      const double turns = std::round((along[previous->first] - start) / (2.0 * kPi));
      if (turns != 0.0)
        for (std::size_t i = ring.first; i < ring.first + ring.count; ++i)
          along[i] += turns * 2.0 * kPi;
    }
    previous = &ring;
  }
}

// The angle that runs along each line, per point: elevation along a rotating scanner's fans, seen
// from `lift` up the turntable axis (or, for fans about a `tilted_axis`, a nodding scanner's, the
// angle from the plane across that axis), azimuth (unwrapped) along a multi-beam ring; ordered
// along the line. Points without a direction take their predecessor's. An arc tangent per point,
// so the lines are dealt out to the threads (a tenth of the map inputs' time on one thread).
std::vector<double> angleAlongLines(const Scan& scan, bool multi_beam, double lift,
                                    const std::optional<Eigen::Vector3d>& tilted_axis,
                                    int threads) {
  std::vector<double> along(scan.size(), 0.0);
  auto alongLine = [&](const ScanLine& line) {
    double previous = 0.0, raw_previous = 0.0;
    bool started = false;
    for (std::size_t i = line.first; i < line.first + line.count; ++i) {
      const Point3f& p = scan.points[i];
      // A point at the origin has no direction. hypot(x, y) + |z| is at least the coordinates'
      // sum over sqrt(2): only a sum below 2e-6 needs the exact test (hypot is slow; this runs
      // for every point).
      const double sum = std::abs(double(p.x)) + std::abs(double(p.y)) + std::abs(double(p.z));
      if (!scan.isValid(i) ||
          (sum <= 2e-6 && std::hypot(double(p.x), double(p.y)) + std::abs(p.z) <= 1e-6)) {
        along[i] = previous;
        continue;
      }
      if (tilted_axis) {
        const Eigen::Vector3d v(p.x, p.y, p.z);
        const double along_axis = v.dot(*tilted_axis);
        previous = std::atan2(along_axis, (v - along_axis * *tilted_axis).norm());
      } else if (!multi_beam) {
        previous = std::atan2(double(p.z) - lift, std::hypot(double(p.x), double(p.y)));
      } else {
        const double raw = std::atan2(double(p.y), double(p.x));
        // The turn from the last azimuth, within half a turn: what std::remainder(step, 2 pi)
        // gives, exactly (Sterbenz: step -/+ 2 pi is exact for |step| within (pi, 2 pi]).
        double step = raw - raw_previous;
        if (step > std::numbers::pi)
          step -= 2.0 * std::numbers::pi;
        else if (step < -std::numbers::pi)
          step += 2.0 * std::numbers::pi;
        previous = started ? previous + step : raw;
        raw_previous = raw;
      }
      started = true;
      along[i] = previous;
    }
  };
  detail::parallelChunks(scan.lines.size(), threads,
                         [&](std::size_t begin, std::size_t end, std::size_t) {
                           for (std::size_t l = begin; l < end; ++l)
                             alongLine(scan.lines[l]);
                         });
  if (multi_beam) alignRingStarts(along, scan.lines);
  return along;
}

// A return that dips back (a point a little off its fan, noise at a grazing angle) would stop the
// walk that pairs the lines (partnersByAngle): the values are made monotone the way the line
// runs, a dip held level at the value before it.
void holdDips(std::vector<double>& along, const ScanLine& line) {
  if (line.count < 2) return;
  const std::size_t last = line.first + line.count - 1;
  const double way = along[last] >= along[line.first] ? 1.0 : -1.0;
  for (std::size_t i = line.first + 1; i <= last; ++i)
    if (way * (along[i] - along[i - 1]) < 0.0) along[i] = along[i - 1];
}

// Sorts values that are nearly in order either way (a ring's azimuths: a few hundred returns of a
// frame lie out of order, each by up to a few dozen places) by insertion, in about one pass;
// values far out of order go to std::sort after a few passes' worth of moves.
void sortNearlySorted(float* first, float* last) {
  if (last - first < 2) return;
  if (last[-1] < first[0]) std::reverse(first, last);
  constexpr std::ptrdiff_t kMovesPerValue = 8;
  std::ptrdiff_t moves_left = kMovesPerValue * (last - first);
  for (float* next = first + 1; next != last; ++next) {
    const float value = *next;
    float* hole = next;
    for (; hole != first && value < hole[-1]; --hole)
      *hole = hole[-1];
    *hole = value;
    moves_left -= next - hole;
    if (moves_left < 0) {
      std::sort(first, last);
      return;
    }
  }
}

// Whether the lines are fans that sweep in elevation, as a turntable's vertical fans do: on the
// median line, at least this share of the beam steps (along_line_step) is gained in elevation
// (counting the rises only, so that fans a file ran together count in full). A nodding scanner's
// tilted fans sweep in azimuth and hardly gain elevation.
constexpr double kElevationShare = 0.5;

bool sweepInElevation(const Scan& scan, const std::vector<double>& along,
                      const SensorGeometry& sensor) {
  if (sensor.kind != SensorKind::kRotating2D || sensor.along_line_step <= 0.0) return false;
  std::vector<double> shares;
  for (const ScanLine& line : scan.lines) {
    if (line.count < 2) continue;
    double rise = 0.0;
    for (std::size_t i = line.first + 1; i < line.first + line.count; ++i)
      rise += std::max(0.0, along[i] - along[i - 1]);
    shares.push_back(rise / (double(line.count - 1) * sensor.along_line_step));
  }
  if (shares.empty()) return false;
  std::nth_element(shares.begin(), shares.begin() + std::ptrdiff_t(shares.size() / 2),
                   shares.end());
  return shares[shares.size() / 2] >= kElevationShare;
}

// A fan starts again where the elevation along a line drops back by more than this many beam
// steps (more than noise or a return a little off its fan, less than any fan's sweep), to a return
// nearer than the last or into the lowest kFanRestartShare of what the fan has swept so far: the
// next fan starts down by the scanner's foot, where this one did. A drop to a farther return
// higher up is the fan itself passing the top of something near and hitting something far beyond
// it, seen from a file's origin below the scanner (28 -> 14 deg up Hannover's facades); split
// there, its upper part sorts between the neighbouring fans as a fan without ground and cuts
// their floor apart.
constexpr double kFanRestartSteps = 10.0;
constexpr double kFanRestartShare = 0.25;

// What the ground is triangulated between, side by side: the scan's lines, or, for a rotating
// scanner, the fans a line holds when its file ran several together (a file whose origin lies on
// the ground gives its loader no jump in elevation to split them at). Each with the angle that
// orders them: the line's (sensor.line_angle), or when lines were split, the direction of the
// fan's points about the turntable axis.
struct Fans {
  std::vector<ScanLine> lines;
  std::vector<double> angles;
};

double squaredRange(const Point3f& p) {
  return double(p.x) * p.x + double(p.y) * p.y + double(p.z) * p.z;
}

Fans fansOf(const Scan& scan, const SensorGeometry& sensor, const std::vector<double>& along) {
  Fans fans;
  const bool split =
      !along.empty() && sensor.kind == SensorKind::kRotating2D && sensor.along_line_step > 0.0;
  const double restart = kFanRestartSteps * sensor.along_line_step;
  for (const ScanLine& line : scan.lines) {
    std::size_t first = line.first;
    const std::size_t end = line.first + line.count;
    double low = split && line.count > 0 ? along[first] : 0.0, high = low;
    for (std::size_t i = line.first + 1; split && i < end; ++i) {
      if (along[i] < along[i - 1] - restart &&
          (squaredRange(scan.points[i]) < squaredRange(scan.points[i - 1]) ||
           along[i] <= low + std::max(restart, kFanRestartShare * (high - low)))) {
        fans.lines.push_back({first, i - first, line.beta});
        first = i;
        low = high = along[i];
        continue;
      }
      low = std::min(low, along[i]);
      high = std::max(high, along[i]);
    }
    fans.lines.push_back({first, end - first, line.beta});
  }
  if (fans.lines.size() == scan.lines.size()) {
    fans.angles = sensor.line_angle;
    return fans;
  }
  // The direction of the fan's points about the axis, weighted as seen from the scanner (a point
  // near the zenith hardly counts), from its part below the horizon where it has one: past the
  // zenith a fan goes on on the other side of the axis.
  for (const ScanLine& fan : fans.lines) {
    double sums[2][2] = {{0.0, 0.0}, {0.0, 0.0}};  // [below the horizon or not][x, y]
    for (std::size_t i = fan.first; i < fan.first + fan.count; ++i) {
      if (!scan.isValid(i)) continue;
      const Point3f& p = scan.points[i];
      const double range = std::sqrt(squaredRange(p));
      if (range <= 0.0) continue;
      const int part = along[i] < 0.0 ? 0 : 1;
      sums[part][0] += p.x / range;
      sums[part][1] += p.y / range;
    }
    const double* sum = sums[0][0] != 0.0 || sums[0][1] != 0.0 ? sums[0] : sums[1];
    fans.angles.push_back(sum[0] == 0.0 && sum[1] == 0.0 ? std::numeric_limits<double>::quiet_NaN()
                                                         : std::atan2(sum[1], sum[0]));
  }
  return fans;
}

// For each point of line a, the point of line b nearest in the angle along the line (both run the
// same way, so one walk over b serves the whole of a).
void partnersByAngle(const std::vector<double>& along, const ScanLine& a, const ScanLine& b,
                     std::vector<std::size_t>& partners) {
  partners.resize(a.count);
  std::size_t j = b.first;
  const std::size_t b_end = b.first + b.count;
  for (std::size_t k = 0; k < a.count; ++k) {
    const double target = along[a.first + k];
    while (j + 1 < b_end && std::abs(along[j + 1] - target) <= std::abs(along[j] - target))
      ++j;
    partners[k] = j;
  }
}

// The lines in the order they lie side by side, and whether the last lies next to the first.
// A rotating scanner's lines go by their turntable angle, not by the file: a 2D field wider than
// half a turn writes a fan's two halves 180 deg apart one after the other, and a turntable that
// overran writes its first lines' neighbours at the end (one pass kept where two overlap: see
// oneFanPerAngle). Sorted by angle, the order starts after
// the widest gap between neighbours; it closes over that gap when the gap is no wider than a
// missing line or two (a full turn: the seam). Multi-beam rings and unknown sensors keep the file
// order and never close.
// A turntable that turned more than once around (it overran, or a scan resumed) covers some
// angles twice, once in each pass; their fans interleave by angle, and a fan of one pass between
// two of the other (its ground unclassified, or the robot moved) would cut the ground into strips.
// Passes are runs of fans in file order, broken where the angle jumps (more than kPassBreak) or
// the run has come once around. Where two passes cover the same angles, the fans of the one with
// fewer ground points there, stretch by stretch of kOverlapStretch line steps, are left out of
// the triangulation (their points still count on the map). Returns which fans to keep.
constexpr double kPassBreak = 15.0 * kPi / 180.0;
constexpr double kOverlapStretch = 4.0;
constexpr double kMostStretches = 1e6;

std::vector<bool> oneFanPerAngle(const Fans& fans, const std::vector<std::int32_t>& ground_of,
                                 const SensorGeometry& sensor) {
  const std::size_t count = fans.lines.size();
  std::vector<bool> keep(count, true);
  if (sensor.kind != SensorKind::kRotating2D || fans.angles.size() != count) return keep;
  struct Pass {
    std::vector<std::size_t> fans;
    double start = 0.0, sweep = 0.0;  // first fan's angle, signed angle turned to the last
  };
  std::vector<Pass> passes;
  double previous = 0.0;
  for (std::size_t f = 0; f < count; ++f) {
    const double angle = fans.angles[f];
    if (!std::isfinite(angle)) continue;
    const double step = passes.empty() ? 0.0 : std::remainder(angle - previous, 2.0 * kPi);
    if (passes.empty() || std::abs(step) > kPassBreak ||
        std::abs(passes.back().sweep + step) >= 2.0 * kPi - 0.5 * sensor.between_line_step) {
      passes.push_back({{f}, angle, 0.0});
    } else {
      passes.back().fans.push_back(f);
      passes.back().sweep += step;
    }
    previous = angle;
  }
  if (passes.size() < 2) return keep;
  // Whether an angle lies within a pass's sweep or less than half a line step beyond its ends: a
  // fan that close to another pass's first or last fan covers the same angle again (a turn that
  // overran by a third of a step, its first fan cut short where the file began, on Hannover's
  // scan100), and the two side by side would leave no ground between them.
  const double margin = 0.5 * sensor.between_line_step;
  auto inside = [&](const Pass& pass, double angle) {
    const double way = pass.sweep >= 0.0 ? 1.0 : -1.0;
    double offset = std::fmod(way * (angle - pass.start), 2.0 * kPi);
    if (offset < 0.0) offset += 2.0 * kPi;
    return offset < std::abs(pass.sweep) + margin || offset > 2.0 * kPi - margin;
  };
  auto groundOf = [&](std::size_t f) {
    std::size_t ground = 0;
    for (std::size_t i = fans.lines[f].first; i < fans.lines[f].first + fans.lines[f].count; ++i)
      ground += ground_of[i] >= 0;
    return ground;
  };
  // Where two passes cover the same angles, the one with more ground points keeps each stretch of
  // kOverlapStretch line steps: a turn whose first fans were cut short where the file began has
  // the floor there in its overrun, and elsewhere in its first pass.
  const double stretch = kOverlapStretch * sensor.between_line_step;
  for (std::size_t a = 0; a < passes.size(); ++a)
    for (std::size_t b = a + 1; b < passes.size(); ++b) {
      // Per stretch of the overlap (counted from b's first fan the way b turned): each pass's
      // fans there and their ground points.
      struct Stretch {
        std::vector<std::size_t> fans[2];
        std::size_t ground[2] = {0, 0};
      };
      std::map<long, Stretch> stretches;
      // The stretch an offset from b's first fan falls in; bounded, so that a degenerate line step
      // cannot overflow it (a turn has a few hundred stretches at most).
      auto stretchOf = [&](double offset) -> long {
        if (stretch <= 0.0) return 0;
        return long(std::min(std::floor((offset + margin) / stretch), kMostStretches));
      };
      const double way = passes[b].sweep >= 0.0 ? 1.0 : -1.0;
      auto add = [&](int side, std::size_t f) {
        double offset = std::fmod(way * (fans.angles[f] - passes[b].start), 2.0 * kPi);
        if (offset < 0.0) offset += 2.0 * kPi;
        if (offset > 2.0 * kPi - margin) offset -= 2.0 * kPi;  // just before b's first fan
        Stretch& at = stretches[stretchOf(offset)];
        at.fans[side].push_back(f);
        at.ground[side] += groundOf(f);
      };
      for (std::size_t f : passes[a].fans)
        if (inside(passes[b], fans.angles[f])) add(0, f);
      for (std::size_t f : passes[b].fans)
        if (inside(passes[a], fans.angles[f])) add(1, f);
      for (const auto& [index, at] : stretches) {
        if (at.fans[0].empty() || at.fans[1].empty()) continue;
        for (std::size_t f : at.fans[at.ground[0] >= at.ground[1] ? 1 : 0])
          keep[f] = false;
      }
    }
  return keep;
}

struct LineOrder {
  std::vector<std::size_t> lines;
  bool closes = false;
};

LineOrder linesSideBySide(const Fans& fans, const std::vector<bool>& keep,
                          const SensorGeometry& sensor) {
  LineOrder order;
  const std::size_t count = fans.lines.size();
  if (fans.angles.size() != count || sensor.kind != SensorKind::kRotating2D) {
    for (std::size_t l = 0; l < count; ++l)
      order.lines.push_back(l);
    return order;
  }
  for (std::size_t l = 0; l < count; ++l)
    if (std::isfinite(fans.angles[l]) && keep[l]) order.lines.push_back(l);
  if (order.lines.size() < 3) return order;
  auto angle = [&](std::size_t l) { return std::remainder(fans.angles[l], 2.0 * kPi); };
  std::stable_sort(order.lines.begin(), order.lines.end(),
                   [&](std::size_t a, std::size_t b) { return angle(a) < angle(b); });
  std::size_t widest = order.lines.size() - 1;  // the gap after this position (wrap: last)
  double widest_gap = angle(order.lines.front()) + 2.0 * kPi - angle(order.lines.back());
  for (std::size_t k = 0; k + 1 < order.lines.size(); ++k) {
    const double gap = angle(order.lines[k + 1]) - angle(order.lines[k]);
    if (gap > widest_gap) {
      widest_gap = gap;
      widest = k;
    }
  }
  std::rotate(order.lines.begin(), order.lines.begin() + std::ptrdiff_t(widest + 1),
              order.lines.end());
  order.closes = widest_gap <= std::max(kSeamSteps * sensor.between_line_step, kLargestSeamGap);
  return order;
}

// Elevation angles tell the beams of a fan apart on the ground only from this high above it [m]:
// a file whose origin lies lower (on the ground) is seen from this high up its turntable axis. A
// fan's plane holds that axis, so from any point on it above the ground the elevation still grows
// along the fan: with the range over the ground, then up what the fan hit.
constexpr double kElevationHeight = 0.5;

}  // namespace

double EdgeLimit::joinedStep(const std::vector<std::int32_t>& ground_of, std::size_t a,
                             std::size_t b, std::size_t c) const {
  const std::int32_t g = ground_of[a];
  const bool one_plane = ground_of[b] == g && ground_of[c] == g;
  const bool off_plane = !continued.empty() && (continued[a] || continued[b] || continued[c]);
  if (one_plane && !off_plane) return 0.0;
  const float za = mapped[a].z(), zb = mapped[b].z(), zc = mapped[c].z();
  const double step = std::max({za, zb, zc}) - std::min({za, zb, zc});
  if (step <= kTouchingStep || plane_heights.empty() || one_plane)
    return step + kJoinedStepUncertainty;
  const Eigen::Vector2d centre =
      ((mapped[a] + mapped[b] + mapped[c]) / 3.0F).head<2>().cast<double>();
  double lowest = std::numeric_limits<double>::max(),
         highest = std::numeric_limits<double>::lowest();
  for (const std::int32_t plane : {ground_of[a], ground_of[b], ground_of[c]}) {
    const double z = heightOnPlane(plane_heights[std::size_t(plane)], centre.x(), centre.y());
    if (!std::isfinite(z)) return std::numeric_limits<double>::infinity();
    lowest = std::min(lowest, z);
    highest = std::max(highest, z);
  }
  return std::max(step, highest - lowest) + kJoinedStepUncertainty;
}

double EdgeLimit::spannedStep(const std::vector<std::int32_t>& ground_of, std::size_t a,
                              std::size_t b, std::size_t c) const {
  const std::int32_t g = ground_of[a];
  if (plane_heights.empty() || ground_of[b] != g || ground_of[c] != g) return 0.0;
  if (!continued.empty() && (continued[a] || continued[b] || continued[c])) return 0.0;
  const std::array<const Eigen::Vector3f*, 3> corners = {&mapped[a], &mapped[b], &mapped[c]};
  const double longest_squared = std::max({(*corners[0] - *corners[1]).head<2>().squaredNorm(),
                                           (*corners[1] - *corners[2]).head<2>().squaredNorm(),
                                           (*corners[0] - *corners[2]).head<2>().squaredNorm()});
  if (longest_squared <= kStepRunLength * kStepRunLength) return 0.0;
  std::array<double, 3> range_squared;  // from the scanner (the map's origin), horizontally
  for (std::size_t i = 0; i < 3; ++i)
    range_squared[i] = corners[i]->head<2>().squaredNorm();
  // Longer than two samples' spacing at its nearest corner's range: no beam saw what it bridges
  // (a lost beam makes it that long already).
  const double nearest = std::sqrt(*std::min_element(range_squared.begin(), range_squared.end()));
  const double sampled = kSpacingsPerEdge * expectedGroundSpacing(sensor, nearest, scanner_height);
  if (longest_squared <= sampled * sampled) return 0.0;
  // How far a corner farther from the scanner lies below a nearer one, about the plane: a drop
  // away from the scanner hides in its own shadow, while a rise towards it is seen (its face's
  // returns) and a rise away from it is seen on its slope.
  const Eigen::Vector3d& plane = plane_heights[std::size_t(g)];
  std::array<double, 3> off_plane;
  for (std::size_t i = 0; i < 3; ++i)
    off_plane[i] = double(corners[i]->z()) - heightOnPlane(plane, corners[i]->x(), corners[i]->y());
  double drop = 0.0;
  for (std::size_t near = 0; near < 3; ++near)
    for (std::size_t far = 0; far < 3; ++far)
      if (range_squared[far] > range_squared[near])
        drop = std::max(drop, off_plane[near] - off_plane[far]);
  return std::isfinite(drop) ? drop : 0.0;
}

LinePairing::LinePairing(const Scan& scan, const std::vector<std::int32_t>& ground_of,
                         const SensorGeometry& sensor, double scanner_height, int threads)
    : multi_beam_(sensor.kind == SensorKind::kMultiBeam) {
  // Ragged lines (sky and no-returns dropped, rings of different lengths) are paired by the angle
  // along the line, not by index (a line with a few more returns up a tree would shift the pairing
  // of all its ground): the azimuth along a ring; the elevation along a fan, seen from at least
  // kElevationHeight above the ground (from the file's origin, every ground point of a file whose
  // origin lies on the ground has an elevation near zero).
  // Lines that sweep in azimuth instead: a nodding scanner's fans (about a tilted axis, from one
  // side of it to the other) by the angle from the plane across that axis, so that a fan that
  // lost returns (octomap's, to the sky and to glass) is not paired by relative index with returns
  // some degrees away; others keep what served them, the elevation from the file's origin when it
  // lies high enough, else the relative index.
  const bool by_angle = !scan.isOrganised();
  const bool nodding = by_angle && !multi_beam_ && sensor.tilted_axis.has_value();
  const double lift = nodding ? 0.0 : std::max(0.0, kElevationHeight - scanner_height);
  along_ = by_angle ? angleAlongLines(scan, multi_beam_, lift,
                                      nodding ? sensor.tilted_axis : std::nullopt, threads)
                    : std::vector<double>{};
  const bool elevation_fans =
      !along_.empty() && !multi_beam_ && !nodding && sweepInElevation(scan, along_, sensor);
  // The elevation from the file's origin is what was computed above when the origin is high
  // enough (no lift); lower, these lines pair by index.
  if (!along_.empty() && !multi_beam_ && !nodding && !elevation_fans &&
      scanner_height < kElevationHeight)
    along_.clear();
  Fans fans = elevation_fans ? fansOf(scan, sensor, along_) : fansOf(scan, sensor, {});
  if (multi_beam_ && !along_.empty()) {
    azimuth_.assign(along_.begin(), along_.end());
    sorted_azimuth_ = azimuth_;
    detail::parallelChunks(fans.lines.size(), threads,
                           [&](std::size_t begin, std::size_t end, std::size_t) {
                             for (std::size_t l = begin; l < end; ++l) {
                               const ScanLine& ring = fans.lines[l];
                               float* first = sorted_azimuth_.data() + ring.first;
                               sortNearlySorted(first, first + ring.count);
                             }
                           });
  }
  // Along a ring too: a return a little out of azimuth order (a frame corrected for the
  // vehicle's motion steps back up to a degree) would hold the walk on it for the rest of the ring.
  if (elevation_fans || nodding || (multi_beam_ && !along_.empty()))
    for (const ScanLine& fan : fans.lines)
      holdDips(along_, fan);
  // Lines side by side: in the order of their angle (file order when the sensor's geometry is
  // unknown); a full turn closes on itself, its last line next to its first.
  LineOrder side_by_side = linesSideBySide(fans, oneFanPerAngle(fans, ground_of, sensor), sensor);
  order_ = std::move(side_by_side.lines);
  lines_ = std::move(fans.lines);
  const std::size_t count = order_.size();
  const bool revolution = count > 2 && side_by_side.closes;
  pairs_ = count == 0 ? 0 : count - 1 + (revolution ? 1 : 0);
}

double LinePairing::widestGap(const ScanLine& line, double low, double high, double enough) const {
  const float* first = sorted_azimuth_.data() + line.first;
  const float* const end = first + line.count;
  // From the last return at or before `low` (or `low`, where the ring starts after it).
  const float* next = std::upper_bound(first, end, float(low));
  double previous = next == first ? low : double(next[-1]);
  double widest = 0.0;
  for (; next != end && previous < high && widest <= enough; ++next) {
    widest = std::max(widest, double(*next) - previous);
    previous = double(*next);
  }
  // Where the ring ends before `high`.
  if (previous < high) widest = std::max(widest, high - previous);
  return widest;
}

void LinePairing::partners(const ScanLine& from, const ScanLine& to,
                           std::vector<std::size_t>& out) const {
  if (!along_.empty()) {
    partnersByAngle(along_, from, to, out);
    return;
  }
  out.resize(from.count);
  for (std::size_t k = 0; k < from.count; ++k)
    out[k] = partner(from, to, k);
}

// Ragged rings (a file that keeps only the returns): two neighbouring returns of a ring and the
// nearest return of the next ring span up to about one and a half of the sensor's steps in
// azimuth (its returns jitter a fraction of a step); a triangle spanning more than
// kNeighbourRingSpan steps has its rings' gaps looked up (it may bridge lost returns, or pair a
// return stored out of azimuth order, whose ring's other returns fill the span: a frame corrected
// for the vehicle's motion has hundreds, up to 6 deg back). A gap wider than kWidestRingGap steps
// lost more than kLostReturnsBridged returns in a row, as an obstacle that returns nothing does.
constexpr double kNeighbourRingSpan = 1.75;
constexpr double kWidestRingGap = double(kLostReturnsBridged) + 1.5;

std::vector<std::array<std::uint32_t, 3>> groundTriangles(
    const Scan& scan, const LinePairing& pairing, const std::vector<std::int32_t>& ground_of,
    const EdgeLimit& limit, int threads, SweepPartners* sweep_partners,
    std::vector<BridgedTriangle>* bridged) {
  std::vector<std::array<std::uint32_t, 3>> triangles;
  auto squaredDistance = [&](std::size_t a, std::size_t b) {
    const Point3f& p = scan.points[a];
    const Point3f& q = scan.points[b];
    const double dx = p.x - q.x, dy = p.y - q.y, dz = p.z - q.z;
    return dx * dx + dy * dy + dz * dz;
  };
  const double fixed_edge_squared = limit.fixed * limit.fixed;
  // A triangle joins two lines. A rotating scanner's fans are paired from the one before (its
  // corner sets the limit, as it always has); two rings are paired in whatever order the file
  // keeps them (KITTI's top down, a ROS driver's bottom up), so the limit is the farthest
  // corner's, the ring whose spacing the edges between the two rings span: the same triangles
  // either way (KITTI 000002 with its rings bottom up showed 81,330 traversable cells against
  // 86,289 as stored).
  const bool rings = pairing.multiBeam();
  auto edgeLimitSquared = [&](std::size_t a, std::size_t b, std::size_t c) {
    if (!rings) return limit.maxEdgeSquared(a);
    return std::max({limit.maxEdgeSquared(a), limit.maxEdgeSquared(b), limit.maxEdgeSquared(c)});
  };
  // Always inlined: called from two loops, the compiler kept it out of line, and every quad of a
  // line without lost returns paid two calls (groundTriangles +13 % instructions on the garage).
  auto add = [&](std::vector<std::array<std::uint32_t, 3>> & out, std::size_t a, std::size_t b,
                 std::size_t c) __attribute__((always_inline)) {
    const std::int32_t g = ground_of[a];
    if (g < 0 || ground_of[b] < 0 || ground_of[c] < 0) return false;
    // Ground of two planes joins only where the two meet with no more than the robot's step.
    if (limit.joinedStep(ground_of, a, b, c) > limit.largest_seam_step) return false;
    // The limit is never below the fixed one: only a longer edge needs the range's.
    const double longest =
        std::max({squaredDistance(a, b), squaredDistance(b, c), squaredDistance(a, c)});
    if (longest > fixed_edge_squared && longest > edgeLimitSquared(a, b, c)) return false;
    out.push_back({std::uint32_t(a), std::uint32_t(b), std::uint32_t(c)});
    return true;
  };
  // A lost return stands in the triangles as the nearer of the two returns around it on its line
  // (its stand-in), where at most kLostReturnsBridged were lost in a row; `lost`: how many. A
  // triangle with two corners on one stand-in is no triangle; its neighbours cover the gap. Not a
  // self-hit: the robot's own body hid the ground there.
  struct Corner {
    std::size_t point;
    std::size_t lost;
  };
  auto lostReturn = [&](std::size_t i) {
    const PointStatus status = scan.status[i];
    return status == PointStatus::kNoReturn || status == PointStatus::kMaxRange;
  };
  // Whether a line holds a lost return at all: most lines of most scans do not, and their pairs
  // are triangulated without stand-ins (one pass over the statuses, not four looks per quad).
  auto anyLost = [&](const ScanLine& line) {
    bool lost = false;
    for (std::size_t i = line.first; i < line.first + line.count; ++i)
      lost |= lostReturn(i);
    return lost;
  };
  auto standIn = [&](const ScanLine& line, std::size_t i) -> Corner {
    if (!lostReturn(i)) return {i, 0};
    std::size_t first = i, last = i;  // the run of lost returns around i
    while (first > line.first && lostReturn(first - 1) && i - first < kLostReturnsBridged)
      --first;
    while (last + 1 < line.first + line.count && lostReturn(last + 1) &&
           last - i < kLostReturnsBridged)
      ++last;
    if (first == line.first || last + 1 == line.first + line.count) return {i, 0};
    const std::size_t before = first - 1, after = last + 1;
    if (!scan.isValid(before) || !scan.isValid(after) || last - first + 1 > kLostReturnsBridged)
      return {i, 0};
    return {i - before <= after - i ? before : after, last - first + 1};
  };
  const std::size_t pairs = pairing.pairs();
  // The ground is uneven along the turn (a wall close by on one side, open floor on the other):
  // several parts per thread keep both threads busy to the end.
  constexpr std::size_t kPartsPerThread = 4;
  std::vector<std::vector<std::array<std::uint32_t, 3>>> parts(
      detail::chunkCount(pairs, threads, kPartsPerThread));
  // The bridging triangles per part, as `parts`.
  std::vector<std::vector<BridgedTriangle>> bridged_parts(bridged ? parts.size() : 0);
  // Along ragged rings, how many of the sensor's steps apart the samples under a triangle of
  // `line` and `other` lie (1 to kLostReturnsBridged + 1), or 0 where it would bridge more lost
  // returns in a row: the widest gap between azimuth neighbours of either ring across the
  // corners' azimuths.
  const double ring_step = limit.sensor.along_line_step;
  const bool ragged_rings = pairing.raggedRings() && ring_step > 0.0;
  auto ringStepsApart = [&](const ScanLine& line, const ScanLine& other, std::size_t a,
                            std::size_t b, std::size_t c) -> std::size_t {
    const double azimuths[] = {pairing.azimuth(a), pairing.azimuth(b), pairing.azimuth(c)};
    const auto [low, high] = std::minmax_element(std::begin(azimuths), std::end(azimuths));
    if (*high - *low <= kNeighbourRingSpan * ring_step) return 1;
    const double widest_allowed = kWidestRingGap * ring_step;
    const double widest = std::max(pairing.widestGap(line, *low, *high, widest_allowed),
                                   pairing.widestGap(other, *low, *high, widest_allowed));
    if (widest > widest_allowed) return 0;
    return std::clamp<std::size_t>(std::size_t(std::lround(widest / ring_step)), 1,
                                   kLostReturnsBridged + 1);
  };
  // Adds the triangle with `steps_apart` (at least that many along its lines), where it may be
  // made: along ragged rings, only where it bridges no more than kLostReturnsBridged in a row.
  auto addApart = [&](std::size_t chunk, const ScanLine& line, const ScanLine& other, std::size_t a,
                      std::size_t b, std::size_t c, std::size_t steps_apart) {
    if (ragged_rings) {
      if (ground_of[a] < 0 || ground_of[b] < 0 || ground_of[c] < 0) return;
      const std::size_t along_rings = ringStepsApart(line, other, a, b, c);
      if (along_rings == 0) return;
      steps_apart = std::max(steps_apart, along_rings);
    }
    if (!add(parts[chunk], a, b, c)) return;
    if (steps_apart > 1 && bridged)
      bridged_parts[chunk].push_back({parts[chunk].back(), std::uint8_t(steps_apart)});
  };
  auto addRingTriangle = [&](std::size_t chunk, const ScanLine& line, const ScanLine& other,
                             std::size_t a, std::size_t b,
                             std::size_t c) { addApart(chunk, line, other, a, b, c, 1); };
  // Out of line, so that `add` stays inlined in the loop over lines that lost nothing.
  auto addCorners = [&](std::size_t chunk, const ScanLine& line, const ScanLine& other,
                        const Corner& a, const Corner& b, const Corner& c)
      __attribute__((noinline)) {
    if (a.point == b.point || b.point == c.point || a.point == c.point) return;
    addApart(chunk, line, other, a.point, b.point, c.point, std::max({a.lost, b.lost, c.lost}) + 1);
  };
  // A multi-beam frame sweeps along its rings, a fraction of a degree between returns: no partners.
  const bool across_lines = sweep_partners && !rings;
  if (across_lines)
    sweep_partners->partners.assign(sweep_partners->points().size(), {kNoPartner, kNoPartner});
  // Each chosen point of a line with its entry, walking `points` beside the line.
  auto forChosen = [&](const ScanLine& line, auto&& visit) {
    const std::vector<std::uint32_t>& chosen = sweep_partners->points();
    auto it = std::lower_bound(chosen.begin(), chosen.end(), line.first);
    for (; it != chosen.end() && *it < line.first + line.count; ++it)
      visit(std::size_t(*it - line.first), std::size_t(it - chosen.begin()));
  };
  detail::parallelChunks(
      pairs, threads,
      [&](std::size_t begin, std::size_t end, std::size_t chunk) {
        std::vector<std::size_t> partners;
        for (std::size_t l = begin; l < end; ++l) {
          const ScanLine& a = pairing.before(l);
          const ScanLine& b = pairing.after(l);
          if (a.count == 0 || b.count == 0) continue;
          pairing.partners(a, b, partners);
          if (ragged_rings && !anyLost(a) && !anyLost(b)) {
            for (std::size_t k = 0; k + 1 < a.count; ++k) {
              const std::size_t a0 = a.first + k, a1 = a0 + 1;
              const std::size_t b0 = partners[k], b1 = partners[k + 1];
              addRingTriangle(chunk, a, b, a0, a1, b0);
              if (b1 != b0) addRingTriangle(chunk, a, b, a1, b1, b0);
            }
          } else if (ragged_rings || anyLost(a) || anyLost(b)) {
            for (std::size_t k = 0; k + 1 < a.count; ++k) {
              const Corner a0 = standIn(a, a.first + k), a1 = standIn(a, a.first + k + 1);
              const Corner b0 = standIn(b, partners[k]), b1 = standIn(b, partners[k + 1]);
              addCorners(chunk, a, b, a0, a1, b0);
              addCorners(chunk, a, b, a1, b1, b0);
            }
          } else {
            for (std::size_t k = 0; k + 1 < a.count; ++k) {
              const std::size_t a0 = a.first + k, a1 = a0 + 1;
              const std::size_t b0 = partners[k], b1 = partners[k + 1];
              add(parts[chunk], a0, a1, b0);
              if (b1 != b0) add(parts[chunk], a1, b1, b0);
            }
          }
          if (!across_lines) continue;
          // Each pair of lines writes the after-partners of a's points and the
          // before-partners of b's: no element is written twice.
          forChosen(a, [&](std::size_t k, std::size_t entry) {
            sweep_partners->partners[entry][1] = std::uint32_t(partners[k]);
          });
          pairing.partners(b, a, partners);
          forChosen(b, [&](std::size_t k, std::size_t entry) {
            sweep_partners->partners[entry][0] = std::uint32_t(partners[k]);
          });
        }
      },
      kPartsPerThread);
  if (bridged)
    for (const auto& part : bridged_parts)
      bridged->insert(bridged->end(), part.begin(), part.end());
  std::size_t total = 0;
  for (const auto& part : parts)
    total += part.size();
  triangles.reserve(total);
  for (auto& part : parts) {
    triangles.insert(triangles.end(), part.begin(), part.end());
    part = {};  // freed as it is copied: the mesh is the largest thing a dense scan's map keeps
  }
  return triangles;
}

}  // namespace clearway::detail
