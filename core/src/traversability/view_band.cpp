#include "view_band.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

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
  std::vector<std::uint8_t> only(grid.cells(), 0);
  if (grid.cells() == 0) return only;
  // Each kind of sparse cell grown by the square, as cellsNearSparse() grows them.
  const cv::Mat square =
      cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * radius + 1, 2 * radius + 1));
  auto near = [&](auto is_kind) {
    cv::Mat kind(grid.height, grid.width, CV_8UC1), grown;
    for (std::size_t cell = 0; cell < grid.cells(); ++cell)
      kind.data[cell] = is_kind(cell) ? 1 : 0;
    cv::dilate(kind, grown, square, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
    return grown;
  };
  const cv::Mat above = near([&](std::size_t cell) { return classes.above_view[cell] != 0; });
  const cv::Mat other = near(
      [&](std::size_t cell) { return classes.sparse[cell] != 0 && classes.above_view[cell] == 0; });
  for (std::size_t cell = 0; cell < grid.cells(); ++cell)
    only[cell] = above.data[cell] && !other.data[cell];
  return only;
}

}  // namespace clearway::detail
