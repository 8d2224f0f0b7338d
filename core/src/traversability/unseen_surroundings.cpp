#include "unseen_surroundings.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core/mat.hpp>
#include <opencv2/imgproc.hpp>

#include "../segmentation/row_dilation.h"

namespace clearway::detail {

void markUnseenSurroundings(const CellClasses& classes, double box_reach_cells,
                            TraversabilityMap& map) {
  const MapGrid& grid = map.grid;
  const auto too_narrow = [&](std::size_t cell) {
    return map.labels[cell] == std::uint8_t(CellLabel::kImpassable) &&
           map.reasons[cell] == std::uint8_t(CellReason::kTooNarrow);
  };
  bool any = false;
  for (std::size_t cell = 0; cell < map.labels.size() && !any; ++cell)
    any = too_narrow(cell);
  if (!any) return;

  cv::Mat blocked(grid.height, grid.width, CV_8UC1);
  for (int row = 0; row < grid.height; ++row) {
    auto* out = blocked.ptr<std::uint8_t>(row);
    for (int column = 0; column < grid.width; ++column)
      out[column] = classes.state[grid.index(column, row)] == CellState::kBlocked ? 255 : 0;
  }
  // One cell more than the reach: the disk's rows are whole cells, and a blocked cell whose
  // corner is within reach must count.
  const int radius = int(std::ceil(box_reach_cells)) + 1;
  const cv::Mat disk =
      cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1));
  cv::Mat near_blocked;
  dilateByCentredRows(blocked, near_blocked, disk);
  for (int row = 0; row < grid.height; ++row) {
    const auto* near = near_blocked.ptr<std::uint8_t>(row);
    for (int column = 0; column < grid.width; ++column) {
      const std::size_t cell = grid.index(column, row);
      if (near[column] || !too_narrow(cell)) continue;
      map.labels[cell] = std::uint8_t(CellLabel::kUnknown);
      map.reasons[cell] = std::uint8_t(CellReason::kUnseenAround);
    }
  }
}

}  // namespace clearway::detail
