#include "view_band.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace clearway::detail {

std::vector<std::uint8_t> cellsAboveTheView(const ScanAnalysis& analysis,
                                            const std::vector<CellState>& state,
                                            const std::vector<std::uint8_t>& own, double band_top) {
  const MapInputs& inputs = analysis.inputs;
  const MapGrid& grid = inputs.grid;
  std::vector<std::uint8_t> above(grid.cells(), 0);
  if (!inputs.view.known()) return above;
  const Eigen::Vector3d scanner = analysis.map_from_scanner.translation();
  // Per reach class, the lowest rise of any sector: a band whose top needs no more is in view
  // whatever its azimuth (a multi-beam head's view is one rise everywhere).
  std::vector<float> lowest(ViewLimit::kReachClasses, std::numeric_limits<float>::infinity());
  for (int sector = 0; sector < ViewLimit::kAzimuthSectors; ++sector)
    for (int c = 0; c < ViewLimit::kReachClasses; ++c)
      lowest[std::size_t(c)] = std::min(
          lowest[std::size_t(c)],
          inputs.view.rise[std::size_t(sector) * ViewLimit::kReachClasses + std::size_t(c)]);
  for (int row = 0; row < grid.height; ++row)
    for (int column = 0; column < grid.width; ++column) {
      const std::size_t cell = grid.index(column, row);
      if (state[cell] != CellState::kGround && state[cell] != CellState::kLowObstacle) continue;
      if (!own.empty() && own[cell]) continue;
      const Eigen::Vector2d away = grid.centre(column, row) - scanner.head<2>();
      const double distance = away.norm();
      if (distance < grid.resolution) continue;
      const double needed = (inputs.ground_height[cell] + band_top - scanner.z()) / distance;
      if (needed <= lowest[std::size_t(ViewLimit::reachClassAt(distance))]) continue;
      if (inputs.view.riseAt(std::atan2(away.y(), away.x()), distance) < needed) above[cell] = 1;
    }
  return above;
}

std::vector<std::uint8_t> sparseOnlyAboveTheView(const CellClasses& classes, const MapGrid& grid,
                                                 int radius) {
  // Running sums over the grid (one row and column of zeros first) of the two kinds of sparse cell.
  const std::size_t stride = std::size_t(grid.width) + 1;
  std::vector<std::uint32_t> above((std::size_t(grid.height) + 1) * stride, 0);
  std::vector<std::uint32_t> other(above.size(), 0);
  for (int row = 0; row < grid.height; ++row)
    for (int column = 0; column < grid.width; ++column) {
      const std::size_t cell = grid.index(column, row);
      const std::size_t at = std::size_t(row + 1) * stride + std::size_t(column + 1);
      const std::uint32_t is_above = classes.above_view[cell];
      const std::uint32_t is_other = classes.sparse[cell] && !classes.above_view[cell];
      above[at] = is_above + above[at - 1] + above[at - stride] - above[at - stride - 1];
      other[at] = is_other + other[at - 1] + other[at - stride] - other[at - stride - 1];
    }
  auto count = [&](const std::vector<std::uint32_t>& sums, int c0, int r0, int c1, int r1) {
    // Cells c0..c1 x r0..r1, inclusive.
    const auto at = [&](int c, int r) { return sums[std::size_t(r) * stride + std::size_t(c)]; };
    return at(c1 + 1, r1 + 1) - at(c0, r1 + 1) - at(c1 + 1, r0) + at(c0, r0);
  };
  std::vector<std::uint8_t> only(grid.cells(), 0);
  for (int row = 0; row < grid.height; ++row)
    for (int column = 0; column < grid.width; ++column) {
      const int c0 = std::max(0, column - radius), c1 = std::min(grid.width - 1, column + radius);
      const int r0 = std::max(0, row - radius), r1 = std::min(grid.height - 1, row + radius);
      only[grid.index(column, row)] =
          count(above, c0, r0, c1, r1) > 0 && count(other, c0, r0, c1, r1) == 0;
    }
  return only;
}

}  // namespace clearway::detail
