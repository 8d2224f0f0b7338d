#include "view_limit.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <vector>

#include "ground_triangles.h"
#include "parallel.h"

namespace clearway {

int ViewLimit::sectorOf(double azimuth) {
  const double turns = (azimuth + std::numbers::pi) / (2.0 * std::numbers::pi);
  const int sector = int(std::floor(turns * kAzimuthSectors));
  if (sector >= 0 && sector < kAzimuthSectors) return sector;  // an atan2's azimuth, bar +pi
  return ((sector % kAzimuthSectors) + kAzimuthSectors) % kAzimuthSectors;
}

int ViewLimit::reachClassAt(double distance) {
  const double reach = std::ceil(std::max(0.0, distance) / kReachStep);
  return int(std::min(reach, double(kReachClasses - 1)));
}

float ViewLimit::riseAt(double azimuth, double distance) const {
  if (!known()) return -std::numeric_limits<float>::infinity();
  return rise[std::size_t(sectorOf(azimuth)) * kReachClasses + std::size_t(reachClassAt(distance))];
}

namespace detail {
namespace {

constexpr float kNoBeam = -std::numeric_limits<float>::infinity();
// A beam closer to vertical than this has no azimuth to speak of, and goes nowhere sideways.
constexpr double kLeastHorizontal = 1e-6;
// Lost beams are placed a sensor's step apart along the fan; a fan angle within kReturnCover steps
// of a return is that return's (no lost beam there).
constexpr double kReturnCover = 1.5;
// Along-fan step used when the sensor's is unknown [rad].
constexpr double kDefaultFanStep = 0.5 * std::numbers::pi / 180.0;

// A return this close to the turntable axis (the sine of its angle from it) has no side of the
// axis to speak of: its direction about the axis is mostly noise. It covers its angle on every side
// of its line.
constexpr double kLeastSideSine = 0.087;  // 5 deg

// Lines with returns either side of a line without any lie at most this far apart about the axis
// for its azimuth to be taken between theirs [rad].
constexpr double kMostInterpolatedTurn = 30.0 * std::numbers::pi / 180.0;

// Sectors between fans take the lower of their sides' views across gaps up to this many turntable
// steps (a fan's beams spread in azimuth once the axis is tilted), and at least kLeastGapSectors.
constexpr double kBridgedSteps = 3.0;
constexpr int kLeastGapSectors = 3;
constexpr int kMostGapSectors = 45;

// The sector of a horizontal direction (x, y), not normalised, without a call to atan2 per beam:
// atan on [0, 1] by a polynomial good to 1e-5 rad (0.0006 deg), then the octant. A beam this close
// to a sector's edge counts for the neighbouring sector as well anyway (widenBySector).
int sectorOfDirection(double x, double y) {
  const double ax = std::abs(x), ay = std::abs(y);
  const double a = std::min(ax, ay) / std::max(ax, ay), s = a * a;
  double angle =
      a *
      (0.99997726 +
       s * (-0.33262347 + s * (0.19354346 + s * (-0.11643287 + s * (0.05265332 - s * 0.0117212)))));
  if (ay > ax) angle = 0.5 * std::numbers::pi - angle;
  if (x < 0.0) angle = std::numbers::pi - angle;
  if (y < 0.0) angle = -angle;
  return ViewLimit::sectorOf(angle);
}

using Table = std::vector<float>;

// Records a beam (map frame, not normalised) that went `reach_class` far.
void record(Table& table, const Eigen::Vector3d& direction, int reach_class) {
  const double horizontal_squared = direction.x() * direction.x() + direction.y() * direction.y();
  if (horizontal_squared < kLeastHorizontal * kLeastHorizontal) return;
  const int sector = sectorOfDirection(direction.x(), direction.y());
  float& rise = table[std::size_t(sector) * ViewLimit::kReachClasses + std::size_t(reach_class)];
  rise = std::max(rise, float(direction.z() / std::sqrt(horizontal_squared)));
}

int reachClassOf(double horizontal_distance) {
  return int(std::min(std::floor(horizontal_distance / ViewLimit::kReachStep),
                      double(ViewLimit::kReachClasses - 1)));
}

Eigen::Vector3d directionOf(const Point3f& p) {
  return Eigen::Vector3d(p.x, p.y, p.z);
}

// The cosine of a return's angle from the turntable axis, z: it falls as the angle grows.
double cosineFromAxis(const Point3f& p) {
  const double norm = std::sqrt(double(p.x) * p.x + double(p.y) * p.y + double(p.z) * p.z);
  return norm > 0.0 ? double(p.z) / norm : 1.0;
}

// Whether a return lies far enough from the axis to tell which side of it it is on.
bool awayFromAxis(const Point3f& p) {
  const double across = double(p.x) * p.x + double(p.y) * p.y;
  return across >= kLeastSideSine * kLeastSideSine * (across + double(p.z) * p.z) &&
         across >= kLeastHorizontal * kLeastHorizontal;
}

// The fan's angles from the axis where lost beams may be, a sensor's step apart: each one's
// direction in the fan's plane, and the cosines of the angles a return covering it lies between.
struct FanAngles {
  std::vector<double> sine, cosine;              // of the angle
  std::vector<double> covered_from, covered_to;  // cosines: from the greater angle to the lesser
};

FanAngles fanAngles(double first, double last, double step) {
  FanAngles angles;
  for (double angle = first; angle <= last; angle += step) {
    angles.sine.push_back(std::sin(angle));
    angles.cosine.push_back(std::cos(angle));
    angles.covered_from.push_back(
        std::cos(std::min(std::numbers::pi, angle + kReturnCover * step)));
    angles.covered_to.push_back(std::cos(std::max(0.0, angle - kReturnCover * step)));
  }
  return angles;
}

// Per line, the azimuth about the axis of a line none of whose beams came back (a half line into
// the sky): its turntable angle, else interpolated in order between the nearest lines with returns
// on either side (the lines are in turntable order) when those lie within kMostInterpolatedTurn
// of each other; NaN for lines with returns, or none to go by (a fan's two halves written one
// after the other would turn half a turn from one to the next).
std::vector<double> azimuthsOfEmptyLines(const Scan& scan) {
  const std::size_t lines = scan.lines.size();
  std::vector<double> own(lines, std::numeric_limits<double>::quiet_NaN());
  std::vector<bool> has_return(lines, false);
  for (std::size_t l = 0; l < lines; ++l) {
    const ScanLine& line = scan.lines[l];
    for (std::size_t i = line.first; i < line.first + line.count; ++i) {
      const Point3f& p = scan.points[i];
      if (scan.isValid(i) && awayFromAxis(p)) {
        own[l] = std::atan2(p.y, p.x);
        has_return[l] = true;
        break;
      }
    }
  }
  std::vector<double> empty(lines, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t l = 0; l < lines; ++l) {
    if (has_return[l]) continue;
    if (std::isfinite(scan.lines[l].beta)) {
      empty[l] = scan.lines[l].beta;
      continue;
    }
    std::size_t before = l, after = l;
    while (before > 0 && !has_return[before])
      --before;
    while (after + 1 < lines && !has_return[after])
      ++after;
    if (!has_return[before] || !has_return[after]) continue;
    const double turn = std::remainder(own[after] - own[before], 2.0 * std::numbers::pi);
    if (std::abs(turn) > kMostInterpolatedTurn) continue;
    empty[l] = own[before] + turn * double(l - before) / double(after - before);
  }
  return empty;
}

// Per sector and reach class: the steepest rise of the beams that went that far or farther.
void keepFarthestReaching(Table& table) {
  for (int sector = 0; sector < ViewLimit::kAzimuthSectors; ++sector) {
    float* rises = table.data() + std::size_t(sector) * ViewLimit::kReachClasses;
    for (int c = ViewLimit::kReachClasses - 2; c >= 0; --c)
      rises[c] = std::max(rises[c], rises[c + 1]);
  }
}

// Each sector also takes its two neighbours' rises: one fan's beams straddle a sector's edge (the
// edge falls anywhere along a fan whose axis is tilted), and its upper beams would otherwise
// count for one sector and its lower ones for the next.
void widenBySector(Table& table) {
  constexpr int kSectors = ViewLimit::kAzimuthSectors;
  const Table own = table;
  for (int sector = 0; sector < kSectors; ++sector)
    for (int side : {kSectors - 1, 1}) {
      const std::size_t from = std::size_t((sector + side) % kSectors) * ViewLimit::kReachClasses;
      const std::size_t to = std::size_t(sector) * ViewLimit::kReachClasses;
      for (int c = 0; c < ViewLimit::kReachClasses; ++c)
        table[to + std::size_t(c)] =
            std::max(table[to + std::size_t(c)], own[from + std::size_t(c)]);
    }
}

// Sectors no beam went through, between sectors that beams did, `most_gap` or fewer in a row: the
// lower of the two sides' rises, per reach class.
void bridgeGaps(Table& table, int most_gap) {
  constexpr int kSectors = ViewLimit::kAzimuthSectors;
  std::vector<float> around(kSectors);
  for (int c = 0; c < ViewLimit::kReachClasses; ++c) {
    for (int sector = 0; sector < kSectors; ++sector)
      around[std::size_t(sector)] =
          table[std::size_t(sector) * ViewLimit::kReachClasses + std::size_t(c)];
    // Start the walk at a sector beams went through, so that no gap wraps past its end.
    int start = 0;
    while (start < kSectors && around[std::size_t(start)] == kNoBeam)
      ++start;
    if (start == kSectors) continue;
    for (int offset = 1; offset < kSectors;) {
      const int sector = (start + offset) % kSectors;
      if (around[std::size_t(sector)] != kNoBeam) {
        ++offset;
        continue;
      }
      int length = 0;
      while (around[std::size_t((sector + length) % kSectors)] == kNoBeam)
        ++length;
      if (length <= most_gap) {
        const float before = around[std::size_t((sector + kSectors - 1) % kSectors)];
        const float after = around[std::size_t((sector + length) % kSectors)];
        for (int k = 0; k < length; ++k)
          table[std::size_t((sector + k) % kSectors) * ViewLimit::kReachClasses + std::size_t(c)] =
              std::min(before, after);
      }
      offset += length;
    }
  }
}

// Records one line's beams at a time: its returns, then its fan's angles without a return.
class LineBeams {
 public:
  LineBeams(const Scan& scan, const Eigen::Matrix3d& rotation, const FanAngles& fan, Table& table)
      : scan_(scan), rotation_(rotation), fan_(fan), table_(table) {}

  // `empty_azimuth`: the line's azimuth about the axis when none of its beams came back.
  void record(const ScanLine& line, double empty_azimuth) {
    sides_used_ = 0;
    near_axis_.clear();
    for (std::size_t i = line.first; i < line.first + line.count; ++i) {
      if (!scan_.isValid(i)) continue;
      const Point3f& p = scan_.points[i];
      const Eigen::Vector3d direction = rotation_ * directionOf(p);
      detail::record(table_, direction, reachClassOf(direction.head<2>().norm()));
      if (!awayFromAxis(p)) {
        near_axis_.push_back(cosineFromAxis(p));
        continue;
      }
      const Eigen::Vector2d across(p.x, p.y);
      Side* side = nullptr;
      for (std::size_t k = 0; k < sides_used_ && !side; ++k)
        if (sides_[k].towards.dot(across) > 0.0) side = &sides_[k];
      if (!side) side = &newSide(across.normalized());
      side->cosine.push_back(cosineFromAxis(p));
    }
    if (std::isfinite(empty_azimuth)) newSide({std::cos(empty_azimuth), std::sin(empty_azimuth)});
    for (std::size_t k = 0; k < sides_used_; ++k) {
      sides_[k].cosine.insert(sides_[k].cosine.end(), near_axis_.begin(), near_axis_.end());
      recordLostBeams(sides_[k]);
    }
  }

 private:
  // One side of the axis a line reaches (a full fan crosses it): its direction about the axis and
  // its returns' cosines from the axis.
  struct Side {
    Eigen::Vector2d towards;
    std::vector<double> cosine;
  };

  // The next side, its buffer kept from line to line.
  Side& newSide(const Eigen::Vector2d& towards) {
    if (sides_used_ == sides_.size()) sides_.emplace_back();
    Side& side = sides_[sides_used_++];
    side.towards = towards;
    side.cosine.clear();
    return side;
  }

  // The fan's angles no return came back from: beams that went on (no echo, out of range).
  void recordLostBeams(Side& side) {
    // In order of their angle from the axis (a line's returns mostly are already, one way or the
    // other).
    if (std::is_sorted(side.cosine.begin(), side.cosine.end()))
      std::reverse(side.cosine.begin(), side.cosine.end());
    else if (!std::is_sorted(side.cosine.begin(), side.cosine.end(), std::greater<>()))
      std::sort(side.cosine.begin(), side.cosine.end(), std::greater<>());
    std::size_t next = 0;
    for (std::size_t k = 0; k < fan_.sine.size(); ++k) {
      while (next < side.cosine.size() && side.cosine[next] > fan_.covered_to[k])
        ++next;
      if (next < side.cosine.size() && side.cosine[next] >= fan_.covered_from[k]) continue;
      const Eigen::Vector3d beam(fan_.sine[k] * side.towards.x(), fan_.sine[k] * side.towards.y(),
                                 fan_.cosine[k]);
      detail::record(table_, rotation_ * beam, ViewLimit::kReachClasses - 1);
    }
  }

  const Scan& scan_;
  const Eigen::Matrix3d& rotation_;
  const FanAngles& fan_;
  Table& table_;
  std::vector<Side> sides_;
  std::size_t sides_used_ = 0;
  std::vector<double> near_axis_;  // cosines of the returns near the axis
};

// A multi-beam head turns every ring all the way round: where its returns are missing (the sky,
// beyond range) it looked all the same, and its top ring's rise is its view in every sector and
// at every reach.
ViewLimit ringsView(const Scan& scan, const Eigen::Matrix3d& rotation, int threads) {
  PerPart<float> steepest(chunkCount(scan.size(), threads), kNoBeam);
  parallelChunks(scan.size(), threads, [&](std::size_t begin, std::size_t end, std::size_t part) {
    for (std::size_t i = begin; i < end; ++i) {
      if (!scan.isValid(i)) continue;
      const Eigen::Vector3d direction = rotation * directionOf(scan.points[i]);
      const double horizontal = direction.head<2>().norm();
      if (horizontal >= kLeastHorizontal)
        steepest[part] = std::max(steepest[part], float(direction.z() / horizontal));
    }
  });
  float top = kNoBeam;
  for (const float rise : steepest)
    top = std::max(top, rise);
  ViewLimit view;
  view.rise.assign(std::size_t(ViewLimit::kAzimuthSectors) * ViewLimit::kReachClasses, top);
  return view;
}

// Lines at least this far apart about the turntable axis make a dense scan's view [rad]: its fans
// a fraction of a degree apart see about what their neighbours see, and a view of fewer beams is
// never higher (cells out of it are only ever more, never fewer).
constexpr double kViewLineSpacing = 0.5 * std::numbers::pi / 180.0;

}  // namespace

ViewLimit viewLimitOf(const Scan& scan, const SensorGeometry& sensor,
                      const Eigen::Isometry3d& map_from_scanner, int threads) {
  // Fans tilted about a horizontal axis (a nodding scanner) and files of no known sensor: what the
  // scanner looked at is not known beyond its returns. A file whose origin lies on the floor (the
  // Hannover scans') does not say where the scanner was: from the floor every low thing near it
  // would hide the band beyond. Neither view is judged.
  const bool rings = sensor.kind == SensorKind::kMultiBeam;
  if ((sensor.kind != SensorKind::kRotating2D && !rings) || sensor.tilted_axis ||
      scan.lines.empty() || map_from_scanner.translation().z() < kLowestScannerHeight)
    return {};
  const Eigen::Matrix3d rotation = map_from_scanner.linear();
  if (rings) return ringsView(scan, rotation, threads);

  // Every line of a scan of fans a degree or so apart, every few of a dense one's.
  const std::size_t stride =
      sensor.between_line_step > 0.0
          ? std::max<std::size_t>(1, std::size_t(kViewLineSpacing / sensor.between_line_step))
          : 1;
  std::vector<std::size_t> lines;
  for (std::size_t l = 0; l < scan.lines.size(); l += stride)
    lines.push_back(l);
  const std::size_t parts = chunkCount(lines.size(), threads);
  // A turntable turns one fan: every line spans the same angles from the axis, from the least to
  // the greatest of all returns' (as cosines: the greatest cosine is the least angle).
  PerPart<double> greatest_cosine(parts, -1.0), least_cosine(parts, 1.0);
  parallelChunks(lines.size(), threads, [&](std::size_t begin, std::size_t end, std::size_t part) {
    for (std::size_t k = begin; k < end; ++k) {
      const ScanLine& line = scan.lines[lines[k]];
      for (std::size_t i = line.first; i < line.first + line.count; ++i)
        if (scan.isValid(i)) {
          const double cosine = cosineFromAxis(scan.points[i]);
          greatest_cosine[part] = std::max(greatest_cosine[part], cosine);
          least_cosine[part] = std::min(least_cosine[part], cosine);
        }
    }
  });
  double greatest = -1.0, least = 1.0;
  for (std::size_t part = 0; part < parts; ++part) {
    greatest = std::max(greatest, greatest_cosine[part]);
    least = std::min(least, least_cosine[part]);
  }
  const FanAngles fan =
      fanAngles(std::acos(greatest), std::acos(least),
                sensor.along_line_step > 0.0 ? sensor.along_line_step : kDefaultFanStep);
  const std::vector<double> empty_line_azimuth = azimuthsOfEmptyLines(scan);

  const std::size_t table_size = std::size_t(ViewLimit::kAzimuthSectors) * ViewLimit::kReachClasses;
  std::vector<Table> tables(parts, Table(table_size, kNoBeam));
  parallelChunks(lines.size(), threads, [&](std::size_t begin, std::size_t end, std::size_t part) {
    LineBeams beams{scan, rotation, fan, tables[part]};
    for (std::size_t k = begin; k < end; ++k)
      beams.record(scan.lines[lines[k]], empty_line_azimuth[lines[k]]);
  });
  Table table = std::move(tables.front());
  for (std::size_t part = 1; part < tables.size(); ++part)
    for (std::size_t i = 0; i < table_size; ++i)
      table[i] = std::max(table[i], tables[part][i]);
  keepFarthestReaching(table);
  widenBySector(table);
  const double used_step_deg = double(stride) * sensor.between_line_step * 180.0 / std::numbers::pi;
  const int most_gap =
      std::clamp(int(std::ceil(kBridgedSteps * used_step_deg)), kLeastGapSectors, kMostGapSectors);
  bridgeGaps(table, most_gap);
  ViewLimit view;
  view.rise = std::move(table);
  return view;
}

}  // namespace detail
}  // namespace clearway
