#include "floor_crossings.h"

#include <cmath>
#include <numbers>
#include <optional>

#include "ground_triangles.h"

namespace clearway::detail {
namespace {

// The returns that anchor a lost run must turn by the sensor's step to within this share of it:
// they lie on one fan, and the run's beams lie between or beyond them on it.
constexpr double kStepTolerance = 0.1;
// An arc this long or longer between two anchors is not measured (the shorter way round between
// two directions is not the fan's beyond half a turn) [rad].
constexpr double kLongestAnchoredArc = 170.0 * std::numbers::pi / 180.0;
// A run at a line's end is continued from its one neighbour and a return at least this many
// steps before it (a longer base measures the fan's turn better) and at most kLongestBase.
constexpr std::size_t kShortestBase = 4;
constexpr std::size_t kLongestBase = 30;
// Only a beam at least this steep below the horizontal is taken to have passed where no floor was:
// a floor met more steeply than that sends a laser's beam back (at 1 m above the floor, within
// 2.7 m of the scanner's foot), while a grazing beam may skim dark or shiny floor and be lost.
constexpr double kSteepestUnreturnedDeg = 20.0;
// A return this far under the reference ground's level [m] is past the floor: a drop's bottom, or
// a wall below the floor's edge (not the floor with its noise, nor a low kerb).
constexpr double kUnderFloor = 0.2;
// A run this long is a drop whatever lies around it (a pit whose far side was seen, a floor's edge
// with the fan's end beyond it): lost echoes come one at a time, and a third of them lost at random
// makes such a run once in 170,000 places (with 6 beams, the simulator's floors showed a few
// crossings in 2 of 36 scans).
constexpr std::size_t kLeastUnexplainedRun = 10;

bool lost(PointStatus status) {
  return status == PointStatus::kNoReturn || status == PointStatus::kMaxRange;
}

// A fan's beams from one measured beam on: the direction `steps` beam steps on from `from`,
// turning towards `towards` (a unit vector at right angles to `from` in the fan's plane).
struct FanArc {
  Eigen::Vector3d from;
  Eigen::Vector3d towards;
  double step = 0.0;  // [rad]
  Eigen::Vector3d beam(double steps) const {
    return std::cos(steps * step) * from + std::sin(steps * step) * towards;
  }
};

// The arc from the return at `start` through the one at `through`, |through - start| beams on,
// or nothing when the two do not turn by the sensor's step.
std::optional<FanArc> arcThrough(const Scan& scan, std::size_t start, std::size_t through,
                                 double sensor_step) {
  const Eigen::Vector3f a(scan.points[start].x, scan.points[start].y, scan.points[start].z);
  const Eigen::Vector3f b(scan.points[through].x, scan.points[through].y, scan.points[through].z);
  if (a.norm() <= 0.0F || b.norm() <= 0.0F) return std::nullopt;
  const Eigen::Vector3d u = a.cast<double>().normalized(), v = b.cast<double>().normalized();
  const double steps = double(through > start ? through - start : start - through);
  const double expected = steps * sensor_step;
  if (expected >= kLongestAnchoredArc) return std::nullopt;
  const double turned = std::atan2(u.cross(v).norm(), u.dot(v));
  if (std::abs(turned - expected) > kStepTolerance * expected) return std::nullopt;
  const Eigen::Vector3d across = v - u.dot(v) * u;
  if (across.norm() <= 0.0) return std::nullopt;
  return FanArc{u, across.normalized(), turned / steps};
}

// The arc that continues beyond `end` the way the fan turned from `base` to it.
std::optional<FanArc> arcBeyond(const Scan& scan, std::size_t end, std::size_t base,
                                double sensor_step) {
  std::optional<FanArc> back = arcThrough(scan, end, base, sensor_step);
  if (back) back->towards = -back->towards;
  return back;
}

// A valid return kShortestBase to kLongestBase beams from `anchor` on the side away from the run
// (`direction` -1: before the anchor, +1: after it), within the line.
std::optional<std::size_t> baseFor(const Scan& scan, const ScanLine& line, std::size_t anchor,
                                   int direction) {
  for (std::size_t steps = kShortestBase; steps <= kLongestBase; ++steps) {
    if (direction < 0 && anchor < line.first + steps) return std::nullopt;
    const std::size_t index = direction < 0 ? anchor - steps : anchor + steps;
    if (index >= line.first + line.count) return std::nullopt;
    if (scan.isValid(index)) return index;
  }
  return std::nullopt;
}

}  // namespace

std::vector<FloorCrossing> lostBeamCrossings(const Scan& scan, const SensorGeometry& sensor,
                                             const Eigen::Isometry3d& map_from_scanner,
                                             const MapGrid& grid,
                                             const std::vector<std::int16_t>& ground_plane) {
  std::vector<FloorCrossing> crossings;
  const double scanner_z = map_from_scanner.translation().z();
  // (Written so that a NaN step or height gives no crossing either.)
  if (sensor.kind != SensorKind::kRotating2D || !(sensor.along_line_step > 0.0) ||
      !(scanner_z > 0.0))
    return crossings;
  const double least_descent = std::sin(kSteepestUnreturnedDeg * std::numbers::pi / 180.0);
  const Eigen::Matrix3d map_from_scanner_rotation = map_from_scanner.linear();
  const Eigen::Vector2d foot = map_from_scanner.translation().head<2>();
  // Where the beam `steps` along `arc` meets the ground level, if it goes down to it.
  auto markCrossing = [&](const FanArc& arc, double steps) {
    const Eigen::Vector3d beam = map_from_scanner_rotation * arc.beam(steps);
    if (!(beam.z() <= -least_descent)) return;  // (a NaN, too)
    const Eigen::Vector2d crossing = foot + beam.head<2>() * (scanner_z / -beam.z());
    const Eigen::Vector2i cell = grid.cellOf(crossing.x(), crossing.y());
    if (!grid.inside(cell.x(), cell.y())) return;
    const std::size_t index = grid.index(cell.x(), cell.y());
    if (ground_plane[index] < 0)
      crossings.push_back({std::uint32_t(index), float(crossing.x()), float(crossing.y())});
  };
  for (const ScanLine& line : scan.lines) {
    const std::size_t end = line.first + line.count;
    for (std::size_t i = line.first; i < end;) {
      if (!lost(scan.status[i])) {
        ++i;
        continue;
      }
      const std::size_t run_first = i;
      while (i < end && lost(scan.status[i]))
        ++i;
      const std::size_t run_last = i - 1;
      // The run's neighbours on its line, where they are measurements.
      const bool before = run_first > line.first && scan.isValid(run_first - 1);
      const bool after = i < end && scan.isValid(i);
      // Echoes lost now and then between seen surfaces (a dark patch, a sensor's dropout) are not
      // a drop: the run must be longer than the ground triangles bridge and open on one side,
      // where its next return lies well under the floor's level (the beam went on down past it),
      // or longer than lost echoes make.
      auto underFloor = [&](std::size_t index) {
        const Eigen::Vector3d p(scan.points[index].x, scan.points[index].y, scan.points[index].z);
        return (map_from_scanner * p).z() < -kUnderFloor;
      };
      const std::size_t run_length = run_last - run_first + 1;
      const bool open_downwards = (before && underFloor(run_first - 1)) || (after && underFloor(i));
      if (run_length <= kLostReturnsBridged ||
          !(open_downwards || run_length >= kLeastUnexplainedRun))
        continue;
      std::optional<FanArc> arc;
      std::size_t anchor = 0;
      if (before && after) {
        anchor = run_first - 1;
        arc = arcThrough(scan, anchor, i, sensor.along_line_step);
      } else if (before) {
        anchor = run_first - 1;
        if (const auto base = baseFor(scan, line, anchor, -1))
          arc = arcBeyond(scan, anchor, *base, sensor.along_line_step);
      } else if (after) {
        anchor = i;
        if (const auto base = baseFor(scan, line, anchor, +1))
          arc = arcBeyond(scan, anchor, *base, sensor.along_line_step);
      }
      if (!arc) continue;
      for (std::size_t k = run_first; k <= run_last; ++k)
        markCrossing(*arc, k > anchor ? double(k - anchor) : double(anchor - k));
    }
  }
  return crossings;
}

std::vector<FloorCrossing> crossingsOfReturnsUnderFloor(
    const std::vector<MapObstacle>& obstacles, const Eigen::Isometry3d& map_from_scanner,
    const MapGrid& grid, const std::vector<std::int16_t>& ground_plane) {
  std::vector<FloorCrossing> crossings;
  const Eigen::Vector3d scanner = map_from_scanner.translation();
  if (!(scanner.z() > 0.0)) return crossings;
  const double least_descent = std::sin(kSteepestUnreturnedDeg * std::numbers::pi / 180.0);
  for (const MapObstacle& o : obstacles) {
    if (!(o.z < -kUnderFloor)) continue;
    const Eigen::Vector3d beam = (Eigen::Vector3d(o.x, o.y, o.z) - scanner).normalized();
    if (!(beam.z() <= -least_descent)) continue;  // (a NaN, too)
    const Eigen::Vector2d crossing = scanner.head<2>() + beam.head<2>() * (scanner.z() / -beam.z());
    const Eigen::Vector2i cell = grid.cellOf(crossing.x(), crossing.y());
    if (!grid.inside(cell.x(), cell.y())) continue;
    const std::size_t index = grid.index(cell.x(), cell.y());
    if (ground_plane[index] < 0)
      crossings.push_back({std::uint32_t(index), float(crossing.x()), float(crossing.y())});
  }
  return crossings;
}

std::vector<FloorCrossing> floorCrossings(const Scan& scan, const SensorGeometry& sensor,
                                          const Eigen::Isometry3d& map_from_scanner,
                                          const MapGrid& grid,
                                          const std::vector<std::int16_t>& ground_plane,
                                          const std::vector<MapObstacle>& obstacles) {
  std::vector<FloorCrossing> crossings =
      lostBeamCrossings(scan, sensor, map_from_scanner, grid, ground_plane);
  const std::vector<FloorCrossing> under_floor =
      crossingsOfReturnsUnderFloor(obstacles, map_from_scanner, grid, ground_plane);
  crossings.insert(crossings.end(), under_floor.begin(), under_floor.end());
  return crossings;
}

}  // namespace clearway::detail
