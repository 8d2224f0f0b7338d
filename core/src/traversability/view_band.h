#pragma once

// Ground over which the robot's band was never in the scanner's view (docs/ALGORITHM.md, "Above
// the scanner's view").

#include <cstdint>
#include <vector>

#include "cell_classes.h"
#include "clearway/segmentation/scan_analysis.h"

namespace clearway::detail {

// 1 on ground cells (kGround, kLowObstacle; not `own`, where the robot itself stands) whose band
// from the ground up to `band_top` [m] above it no beam of the scan rose through: the top of the
// band over the cell's centre lies above every beam about its azimuth that went that far
// (MapInputs::view). An overhang there would never have been measured. Cells under the scanner
// (within a cell of its foot) are the scanner's own mount and are not marked.
std::vector<std::uint8_t> cellsAboveTheView(const ScanAnalysis& analysis,
                                            const std::vector<CellState>& state,
                                            const std::vector<std::uint8_t>& own, double band_top);

// Per cell: 1 where a square of `radius` cells about it holds a cell above the view and no other
// sparse cell: where the robot's box fits only over sparse ground there, the view is why.
std::vector<std::uint8_t> sparseOnlyAboveTheView(const CellClasses& classes, const MapGrid& grid,
                                                 int radius);

}  // namespace clearway::detail
