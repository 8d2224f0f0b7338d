#include "unseen_surroundings.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/core/mat.hpp>

#include "../segmentation/row_dilation.h"

namespace clearway::detail {
namespace {

// The cells whose centres lie within `radius` cells of the middle one: each row a run centred on
// it, as dilateByCentredRows takes them (OpenCV's ellipse element reaches a little beyond).
cv::Mat diskElement(int radius) {
  cv::Mat disk = cv::Mat::zeros(2 * radius + 1, 2 * radius + 1, CV_8UC1);
  for (int dy = -radius; dy <= radius; ++dy) {
    const int half = int(std::floor(std::sqrt(double(radius * radius - dy * dy))));
    disk.row(dy + radius).colRange(radius - half, radius + half + 1).setTo(255);
  }
  return disk;
}

}  // namespace

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
  // One cell more than the reach: a blocked cell whose corner is within reach must count.
  cv::Mat near_blocked;
  dilateByCentredRows(blocked, near_blocked, diskElement(int(std::ceil(box_reach_cells)) + 1));
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
