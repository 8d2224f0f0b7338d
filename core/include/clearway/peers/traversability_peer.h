#pragma once

// The textbook way to move a box over an occupancy grid, as a peer for our traversability stage:
// every cell that is not free is dilated with the robot's footprint rotated to each orientation
// (OpenCV `dilate`), and a free cell is traversable when one dilation leaves it free. It starts
// from the same cell classes our map does and tries the same orientations, but has no exact
// narrow-passage check and no tolerance for sampling gaps.

#include <cstdint>
#include <vector>

#include "clearway/segmentation/params.h"
#include "clearway/segmentation/scan_analysis.h"

namespace clearway::peers {

// Labels as TraversabilityMap::labels (row 0 = smallest map y): 1 where the box fits, 4 where
// it does not or the cell is blocked, 0 unobserved. `yaws` are map-frame orientations [rad].
std::vector<std::uint8_t> dilateTraversability(const ScanAnalysis& analysis,
                                               const RobotParams& robot, const MapParams& params,
                                               const std::vector<double>& yaws, int threads);

}  // namespace clearway::peers
