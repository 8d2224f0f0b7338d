#pragma once

// The reachability search, for computeTraversability (which owns the footprint tests) and the
// goal query (path_planning.cpp): the search over (cell, orientation) states.

#include <cstdint>
#include <vector>

#include "clearway/traversability/reachability.h"
#include "clearway/traversability/traversability_map.h"

namespace clearway::detail {

// The eight neighbours of a cell (column and row steps): the four sides first, then the corners.
inline constexpr int kNeighbourColumns[8] = {1, -1, 0, 0, 1, 1, -1, -1};
inline constexpr int kNeighbourRows[8] = {0, 0, 1, -1, 1, -1, 1, -1};

// For each orientation, the orientations one turn step away (sorted by angle, modulo 180 deg).
std::vector<std::vector<int>> turnNeighbours(const std::vector<double>& yaws);

// The cells whose fits the search from the robot's pose (map.robot_pose, map.robot_orientation)
// may read and that the box fits in somewhere (`fit_orientation` not kNoOrientation, one entry per
// cell): the robot's own cell, and every such cell connected to it through such cells (eight
// neighbours). The search enters no other cell: a move crosses eight-connected cells and needs a
// fitting pose at each. Cells where nothing fits are looked at too, but their fits are all
// kBlocked. Empty when the search cannot
// start (no orientation, the pose off the map).
std::vector<std::uint32_t> cellsTheSearchMayEnter(const TraversabilityMap& map,
                                                  const std::vector<std::uint8_t>& fit_orientation);

// Fills map.reach, map.reachable_cells and map.pose_fit from the robot's pose
// (map.robot_pose, map.robot_orientation), given the fit of every pose (PoseFit per
// cell * map.yaws.size() + k; kBlocked wherever the box does not fit or the cell is not free) and
// `may_enter`, cellsTheSearchMayEnter's cells: only their fits are read (anywhere else the box
// fits nowhere the search can meet).
void searchReachable(TraversabilityMap& map, const std::vector<std::uint8_t>& pose_fits,
                     const std::vector<std::uint32_t>& may_enter);

}  // namespace clearway::detail
