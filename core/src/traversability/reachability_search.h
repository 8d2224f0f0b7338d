#pragma once

// The reachability search, for computeTraversability: it owns the footprint tests, this owns the
// search over (cell, orientation) states.

#include <functional>
#include <vector>

#include "clearway/traversability/reachability.h"
#include "clearway/traversability/traversability_map.h"

namespace clearway::detail {

// For each orientation, the orientations one turn step away (sorted by angle, modulo 180 deg).
std::vector<std::vector<int>> turnNeighbours(const std::vector<double>& yaws);

// Fills map.reach, map.reachable_cells and map.pose_fit from the robot's pose
// (map.robot_pose, map.robot_orientation); fitAt(column, row, k) tests one pose and is called
// from `threads` threads at once.
void searchReachable(TraversabilityMap& map, const std::function<PoseFit(int, int, int)>& fitAt,
                     int threads);

}  // namespace clearway::detail
