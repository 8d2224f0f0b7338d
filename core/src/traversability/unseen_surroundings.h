#pragma once

// Red means something seen stops the robot. On ground seen among unobserved cells (a multi-beam
// frame's road between its rings, the edge of what a scan saw, the shadow behind an obstacle) the
// robot's box may fit in no orientation only because the cells around it were not seen; calling
// such a cell "too narrow" tells the operator of a wall that nobody saw.

#include "cell_classes.h"
#include "clearway/traversability/traversability_map.h"

namespace clearway::detail {

// Every "too narrow" cell of `map` with no blocked cell of `classes` within `box_reach_cells` (the
// robot's enlarged box's circumscribed radius) becomes unknown, reason kUnseenAround. Where a
// blocked cell is that near, the cell stays red: what was seen may be what keeps the box out.
void markUnseenSurroundings(const CellClasses& classes, double box_reach_cells,
                            TraversabilityMap& map);

}  // namespace clearway::detail
