#pragma once

// Why the robot's reach stops short, in words for the operator: a reach of a few cells beside
// thousands where the box fits says nothing by itself. Under a car-mounted multi-beam sensor the
// rings never see the ground around the car, so the robot stands on an island of its own cells;
// in a room, a door too narrow shuts it in. The edge of the reach tells the two apart.

#include <string>

#include "clearway/traversability/traversability_map.h"

namespace clearway::detail {

// Empty while the robot reaches at least as many cells as it fits in but cannot reach
// (map.reachable_cells, map.fits_not_reachable_cells). Otherwise what mostly stops it within
// `box_reach_cells` (the box's circumscribed radius) of its reach - unobserved ground, or the
// reason cells there block - and how far away the nearest cell is where it fits but cannot get.
std::string describeReachLimit(const TraversabilityMap& map, double box_reach_cells);

}  // namespace clearway::detail
