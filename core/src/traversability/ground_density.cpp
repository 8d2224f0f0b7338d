#include "clearway/traversability/ground_density.h"

#include <numbers>

namespace clearway {
namespace {

// The range is searched outwards in steps this fine, up to the farthest a map reaches [m].
constexpr double kRangeStep = 0.01;
constexpr double kFarthestRange = 500.0;

}  // namespace

SensorGeometry rosiGeometry(int lines, double along_step_deg) {
  SensorGeometry sensor;
  sensor.kind = SensorKind::kRotating2D;
  sensor.lines = std::size_t(lines > 0 ? lines : 0);
  sensor.along_line_step = along_step_deg * std::numbers::pi / 180.0;
  sensor.between_line_step = lines > 0 ? 2.0 * std::numbers::pi / lines : 0.0;
  sensor.closed_turn = lines > 0;
  return sensor;
}

double vouchedGroundRange(const SensorGeometry& sensor, double height, double max_step) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const double largest_hidden = kSpacingPerStep * max_step;
  double vouched = 0.0;
  // The widest hidden obstacle grows with the range (both terms do), so the first range that
  // fails ends the search.
  for (double range = kRangeStep; range <= kFarthestRange; range += kRangeStep) {
    if (hiddenObstacleSize(sensor, {range, 0.0, -height}, up, height) > largest_hidden) break;
    vouched = range;
  }
  return vouched;
}

}  // namespace clearway
