#pragma once

// The reachability search, for computeTraversability: it owns the footprint tests, this owns the
// search over (cell, orientation) states.

#include <cstdint>
#include <vector>

#include "clearway/traversability/reachability.h"
#include "clearway/traversability/traversability_map.h"

namespace clearway::detail {

// For each orientation, the orientations one turn step away (sorted by angle, modulo 180 deg).
std::vector<std::vector<int>> turnNeighbours(const std::vector<double>& yaws);

// Fills map.reach, map.reachable_cells and map.pose_fit from the robot's pose
// (map.robot_pose, map.robot_orientation), given the fit of every pose (PoseFit per
// cell * map.yaws.size() + k; kBlocked wherever the box does not fit or the cell is not free).
void searchReachable(TraversabilityMap& map, const std::vector<std::uint8_t>& pose_fits);

}  // namespace clearway::detail
