#include "clearway/traversability/ground_density.h"

#include <numbers>

namespace clearway {
namespace {

// Farther than any map reaches [m].
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
  return vouchedRange(sensor, height, kSpacingPerStep * max_step, kFarthestRange);
}

}  // namespace clearway
