#pragma once

// Where beams went down through the level the robot stands on, over ground no return showed: the
// floor ends there (a drop, a pit, a ledge's edge, the near side of a hole whose far wall was
// seen).
//
// A beam that came back from well under the floor's level passed it on the way. A beam that came
// back with nothing did too, where it pointed steeply enough that a floor would have sent it back:
// a rotating 2D scanner's line is a fan (one plane through the scanner, its beams one angular step
// apart), and a lost return (no echo, or a saturated range) keeps its place in its line, so its
// beam's direction is the fan's at that place, measured from the valid returns around it.
//
// Where the floor ends is not floor the robot's own body hid either. The map blocks there as at a
// drop whose bottom was seen, and the robot's guessed place keeps off it (cell_classes.cpp,
// reachability.cpp).

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "clearway/scan.h"
#include "clearway/segmentation/scan_analysis.h"
#include "clearway/sensor_geometry.h"

namespace clearway::detail {

// Every crossing of the scan: its lost beams' (lostBeamCrossings), then its returns' from under the
// floor among `obstacles` (crossingsOfReturnsUnderFloor).
std::vector<FloorCrossing> floorCrossings(const Scan& scan, const SensorGeometry& sensor,
                                          const Eigen::Isometry3d& map_from_scanner,
                                          const MapGrid& grid,
                                          const std::vector<std::int16_t>& ground_plane,
                                          const std::vector<MapObstacle>& obstacles);

// Where a lost return's beam went down through the map's z = 0 (the reference ground's level) over
// an unobserved cell (ground_plane < 0), at least kSteepestUnreturnedDeg below the horizontal: a
// floor met that steeply sends the beam back. Empty for a sensor that is not a rotating 2D scanner
// (a multi-beam ring is a cone, not a fan), and nothing for lost runs whose neighbouring returns do
// not turn by the sensor's step (their directions cannot be told).
std::vector<FloorCrossing> lostBeamCrossings(const Scan& scan, const SensorGeometry& sensor,
                                             const Eigen::Isometry3d& map_from_scanner,
                                             const MapGrid& grid,
                                             const std::vector<std::int16_t>& ground_plane);

// Where the beams of `obstacles` (map positions) that lie well under the map's z = 0 went down
// through it over an unobserved cell, at least kSteepestUnreturned below the horizontal (the same
// reach as the lost beams': farther out, the reference plane only approximates uneven ground).
std::vector<FloorCrossing> crossingsOfReturnsUnderFloor(
    const std::vector<MapObstacle>& obstacles, const Eigen::Isometry3d& map_from_scanner,
    const MapGrid& grid, const std::vector<std::int16_t>& ground_plane);

}  // namespace clearway::detail
