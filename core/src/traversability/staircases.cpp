// A detected staircase on the map and per robot (docs/ALGORITHM.md, 4b): its footprint and
// surface, the cells it covers, the points on it, whether a robot climbs it, and how the map and
// the console show it. Detection itself is in segmentation/stairs.cpp.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "clearway/segmentation/scan_analysis.h"
#include "clearway/segmentation/stairs.h"
#include "clearway/traversability/traversability_map.h"

namespace clearway {
namespace {

// Stair surface points lie within this of the fitted treads and risers [m].
constexpr double kSurfaceMargin = 0.05;

}  // namespace

double Staircase::yawDegrees() const {
  return std::atan2(up.y(), up.x()) * 180.0 / std::numbers::pi;
}

double Staircase::slopeDegrees() const {
  return std::atan2(rise, tread) * 180.0 / std::numbers::pi;
}

std::vector<Eigen::Vector2d> Staircase::footprint() const {
  return {start() * up + across_min * across, end() * up + across_min * across,
          end() * up + across_max * across, start() * up + across_max * across};
}

bool Staircase::containsPoint(const Eigen::Vector3d& p) const {
  const Eigen::Vector2d xy = p.head<2>();
  const double u = up.dot(xy), v = across.dot(xy);
  if (v < across_min - kSurfaceMargin || v > across_max + kSurfaceMargin) return false;
  if (u < start() - kSurfaceMargin || u > end() + kSurfaceMargin) return false;
  // The riser at or just behind the point: the point is on it, or on the tread in front of it.
  const auto k =
      std::size_t(std::upper_bound(riser_offsets.begin(), riser_offsets.end(), u + kSurfaceMargin) -
                  riser_offsets.begin() - 1);
  const double foot = k == 0 ? riser_tops[0] - rise : riser_tops[k - 1];
  return p.z() >= foot - kSurfaceMargin && p.z() <= riser_tops[k] + kSurfaceMargin;
}

std::vector<std::int16_t> staircaseCells(const std::vector<Staircase>& staircases,
                                         const MapGrid& grid) {
  if (staircases.empty()) return {};
  std::vector<std::int16_t> cells(grid.cells(), -1);
  for (std::size_t s = 0; s < staircases.size(); ++s) {
    const Staircase& stairs = staircases[s];
    Eigen::AlignedBox2d box;
    for (const Eigen::Vector2d& corner : stairs.footprint())
      box.extend(corner);
    const Eigen::Vector2i low = grid.cellOf(box.min().x(), box.min().y());
    const Eigen::Vector2i high = grid.cellOf(box.max().x(), box.max().y());
    for (int row = std::max(low.y(), 0); row <= std::min(high.y(), grid.height - 1); ++row)
      for (int column = std::max(low.x(), 0); column <= std::min(high.x(), grid.width - 1);
           ++column) {
        const Eigen::Vector2d centre = grid.centre(column, row);
        const double u = stairs.up.dot(centre), v = stairs.across.dot(centre);
        if (u >= stairs.start() && u <= stairs.end() && v >= stairs.across_min &&
            v <= stairs.across_max)
          cells[grid.index(column, row)] = std::int16_t(s);
      }
  }
  return cells;
}

std::string stairVerdict(const Staircase& stairs, const RobotParams& robot) {
  auto metres = [](double value) { return std::to_string(int(std::lround(value * 100))) + " cm"; };
  auto degrees = [](double value) { return std::to_string(int(std::lround(value))) + " deg"; };
  if (stairs.rise > robot.max_stair_rise)
    return "risers of " + metres(stairs.rise) + ", the robot climbs " +
           metres(robot.max_stair_rise);
  if (stairs.slopeDegrees() > robot.max_stair_slope_deg)
    return "a " + degrees(stairs.slopeDegrees()) + " flight, the robot climbs " +
           degrees(robot.max_stair_slope_deg);
  if (stairs.width() < robot.width)
    return "the flight is " + metres(stairs.width()) + " wide, the robot " + metres(robot.width);
  return "";
}

std::string describeStaircase(const Staircase& stairs, const RobotParams& robot) {
  auto rounded = [](double value) { return std::to_string(int(std::lround(value))); };
  const std::string verdict = stairVerdict(stairs, robot);
  return std::to_string(stairs.steps()) + " steps, rise " + rounded(stairs.rise * 100) +
         " cm, tread " + rounded(stairs.tread * 100) + " cm, " + rounded(stairs.slopeDegrees()) +
         " deg, climbs towards " + rounded(stairs.yawDegrees()) + " deg; " +
         (verdict.empty() ? "climbable with care" : "not climbable: " + verdict);
}

void labelStairs(const ScanAnalysis& analysis, const RobotParams& robot, TraversabilityMap& map) {
  const StairDetection& detection = analysis.stairs;
  if (detection.staircases.empty() || detection.cell_staircase.size() != map.labels.size()) return;
  // Per staircase: the label and, when the robot cannot climb it, why.
  std::vector<std::pair<CellLabel, CellReason>> verdicts;
  for (const Staircase& stairs : detection.staircases) {
    if (stairVerdict(stairs, robot).empty())
      verdicts.emplace_back(CellLabel::kStairs, CellReason::kNone);
    else if (stairs.rise > robot.max_stair_rise ||
             stairs.slopeDegrees() > robot.max_stair_slope_deg)
      verdicts.emplace_back(CellLabel::kImpassable, CellReason::kStairsTooSteep);
    else
      verdicts.emplace_back(CellLabel::kImpassable, CellReason::kTooNarrow);
  }
  for (std::size_t cell = 0; cell < map.labels.size(); ++cell) {
    const int s = detection.cell_staircase[cell];
    if (s < 0) continue;
    map.labels[cell] = std::uint8_t(verdicts[std::size_t(s)].first);
    map.reasons[cell] = std::uint8_t(verdicts[std::size_t(s)].second);
    map.orientation[cell] = kNoOrientation;
  }
}

void classifyStairPoints(const Scan& scan, const ScanAnalysis& analysis,
                         std::vector<PointClass>& classes) {
  const auto& staircases = analysis.stairs.staircases;
  if (staircases.empty()) return;
  // Most points are nowhere near a flight: one box around all of them rules those out cheaply.
  Eigen::AlignedBox2f near;
  for (const Staircase& stairs : staircases)
    for (const Eigen::Vector2d& corner : stairs.footprint())
      near.extend(corner.cast<float>());
  near.extend(near.min() - Eigen::Vector2f::Constant(float(kSurfaceMargin)));
  near.extend(near.max() + Eigen::Vector2f::Constant(float(kSurfaceMargin)));
  const Eigen::Matrix3f rotation = analysis.map_from_scanner.linear().cast<float>();
  const Eigen::Vector3f translation = analysis.map_from_scanner.translation().cast<float>();
  for (std::size_t i = 0; i < scan.size() && i < classes.size(); ++i) {
    if (!scan.isValid(i)) continue;
    const Point3f& p = scan.points[i];
    const Eigen::Vector3f mapped = rotation * Eigen::Vector3f(p.x, p.y, p.z) + translation;
    if (!near.contains(mapped.head<2>())) continue;
    const Eigen::Vector3d m = mapped.cast<double>();
    for (const Staircase& stairs : staircases)
      if (stairs.containsPoint(m)) {
        classes[i] = PointClass::kStairs;
        break;
      }
  }
}

}  // namespace clearway
