#pragma once

// How densely a scanner samples the ground, and how far from it the map can vouch for the floor
// (docs/ALGORITHM.md, "Sparse scans never lie"): for the console's Scanner tab, before a scan.

#include "clearway/sensor_geometry.h"

namespace clearway {

// Ground samples at most this many robot steps apart leave no room for a hidden obstacle taller
// than the step: a triangle whose edges are all at most 2 s holds no square wider than s.
inline constexpr double kSpacingPerStep = 2.0;

// A RoSi turning `lines` half lines per revolution, `along_step_deg` between the beams of a line.
SensorGeometry rosiGeometry(int lines, double along_step_deg);

// How far from the scanner's foot flat ground is vouched for, the scanner `height` above it with
// its sweep axis upright: the farthest range out to which no obstacle taller than `max_step` can
// stand between the samples unseen. 0 when nothing is (or the sensor is unknown) [m].
double vouchedGroundRange(const SensorGeometry& sensor, double height, double max_step);

}  // namespace clearway
