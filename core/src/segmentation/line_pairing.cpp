// Which lines lie side by side and how their points pair up (docs/ALGORITHM.md, section 5): the
// angle along each line, the fans a file ran together, the lines in the order of their angle (a
// full turn closed), one pass per angle where a turntable overran, and a ragged ring's azimuth
// gaps.

#include "line_pairing.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <optional>

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

}  // namespace clearway::detail
