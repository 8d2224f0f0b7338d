#pragma once

// Fits the robot cannot drive out of: a robot wider than long fits in a door narrower than its
// width turned across it (its length across the opening, its width straddling the wall), but it
// drives along its length, and there it can move no farther than the door's width less its
// length. Such cells looked like a passage on the map, joining a corridor to a room the robot
// cannot enter (docs/ALGORITHM.md, "Room to drive").

#include <cstdint>
#include <vector>

#include "clearway/segmentation/params.h"
#include "clearway/traversability/traversability_map.h"

namespace clearway::detail {

struct CellClasses;
struct Footprints;
class FootprintTester;

// Cells where the box fits, that the robot does not reach, and where in no orientation it fits in
// can it drive back and forth along its heading over the robot's width less its length (plus a
// cell for where in its cell a fit may lie) become impassable, too narrow. Nothing changes for a
// robot at least as long as it is wide: turned across a passage narrower than its width it would
// not fit. `tester` and `pose_fits` are the placement's that takes sparse ground as ground (the
// search's); the tests made here are recorded in `pose_fits`.
void markFitsWithoutRoomToDrive(TraversabilityMap& map, const CellClasses& classes,
                                const Footprints& footprints, const FootprintTester& tester,
                                std::vector<std::uint8_t>& pose_fits, const RobotParams& robot,
                                int threads);

}  // namespace clearway::detail
