#pragma once

// What kind of sensor took a scan, read from the geometry of its lines: a rotating 2D scanner (the
// RoSi: half lines fanning about a turntable axis) or a multi-beam LiDAR (Velodyne, Ouster: one
// ring per beam, each a full turn in azimuth), the angular steps along and between lines, and
// whether the lines close a full turn (the last line neighbours the first). Pipeline parameters
// that depend on the sensor (line gaps, triangle edges, the density check) are derived from it.

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <string_view>
#include <vector>

#include "clearway/scan.h"

namespace clearway {

enum class SensorKind { kUnknown, kRotating2D, kMultiBeam };
std::string_view sensorKindName(SensorKind kind);  // "unknown", "rotating 2D", "multi-beam"

struct SensorGeometry {
  SensorKind kind = SensorKind::kUnknown;
  std::size_t lines = 0;  // scan lines; the rings of a multi-beam sensor
  // Median angle between neighbouring returns of one line [rad]; 0 when unknown.
  double along_line_step = 0.0;
  // Median angle between neighbouring lines [rad]: the turntable's step for a rotating 2D scanner,
  // the elevation step between rings for a multi-beam one; 0 when unknown.
  double between_line_step = 0.0;
  // The lines go once around the turntable axis and the last one lies next to the first, so the
  // two are neighbours (a partial turn is not closed). Multi-beam rings are not lines of a turn.
  bool closed_turn = false;
  // Per line, the angle that orders lines side by side: the turntable angle (beta, or the
  // direction of the line's points about z) of a rotating scanner's line, the elevation of a
  // ring [rad]; NaN for a line without a valid return. A scanner whose 2D field spans more than
  // half a turn writes a fan's two halves one after the other, 180 deg apart: the neighbour of a
  // line is the next one in this angle, not in the file.
  std::vector<double> line_angle;
  // The axis a rotating 2D scanner's fans turn about, when it lies far from z (a nodding scanner:
  // fans tilted about a horizontal axis, each sweeping from one side to the other): estimated
  // from the fans' planes, and line_angle is taken about it. Unset: z (vertical fans), or rings.
  std::optional<Eigen::Vector3d> tilted_axis;
};

// Reads the geometry from the valid points (sensor at the origin) and the lines' beta angles; the
// lines are read on up to `threads` threads (the result does not depend on it).
SensorGeometry describeSensor(const Scan& scan, int threads = 1);

// The largest gap expected between neighbouring ground samples at horizontal distance `range` from
// a sensor `height` above flat ground. A step that moves the beam towards or away from the sensor
// is stretched on the ground to (range^2 + height^2) / height x step (a grazing beam): a RoSi's
// step along its fans, a multi-beam ring's elevation step, a nodding scanner's step from fan to
// fan. A step that moves it sideways makes an arc of range x step: a RoSi's turntable step, the
// azimuth step along a ring, the step along a nodding scanner's fan. An obstacle narrower and
// shorter than this spacing can stand between samples unseen (see docs/ALGORITHM.md, "Sparse
// scans never lie"). Returns metres; infinity for a sensor at or below the ground.
double expectedGroundSpacing(const SensorGeometry& sensor, double range, double height);

// How wide an obstacle could stand on the ground at `point` (scanner frame; `up` is gravity's up
// in that frame, the sensor `height` above that ground) between the sensor's samples without any
// beam touching it [m]. Across the direction the sensor sweeps (a rotating scanner's turntable, a
// ring's azimuth) neighbouring beams are `distance from the sweep's axis x step` apart, and
// nothing between them is seen, however tall. Within a fan (a RoSi line) or from ring to ring,
// the step moves the ground sample; the part of that move along the beam is protected, since the
// farther beam passes over the gap at most `gap x height / range` high and so hits an obstacle
// half the gap's width high (it counts as `2 x range x step`); the part sideways is not. A
// nodding scanner's fans (`tilted_axis`) are the other way round: a fan's own step leaves the
// sideways gap and the step from fan to fan moves the sample outwards; both are worked out about
// that axis. A cell is vouched for where this is at most twice the robot's step. Infinity when
// unknown.
double hiddenObstacleSize(const SensorGeometry& sensor, const Eigen::Vector3d& point,
                          const Eigen::Vector3d& up, double height);

// The farthest horizontal distance from the sensor, up to `limit`, out to which flat ground
// `height` below it is sampled densely enough that no obstacle wider than `largest_hidden` can hide
// (hiddenObstacleSize() <= largest_hidden all the way out) [m]. Farther ground can never be vouched
// for; a multi-beam frame's map stops there (docs/ALGORITHM.md, "Multi-beam frames"). `limit` for
// an unknown sensor.
double vouchedRange(const SensorGeometry& sensor, double height, double largest_hidden,
                    double limit);

}  // namespace clearway
