#include "unseen_surroundings.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace clearway::detail {

void markUnseenSurroundings(const CellClasses& classes, double box_reach_cells,
                            TraversabilityMap& map) {
  const MapGrid& grid = map.grid;
  const auto too_narrow = [&](std::size_t cell) {
    return map.labels[cell] == std::uint8_t(CellLabel::kImpassable) &&
           map.reasons[cell] == std::uint8_t(CellReason::kTooNarrow);
  };
  if (std::none_of(map.labels.begin(), map.labels.end(), [](std::uint8_t label) {
        return label == std::uint8_t(CellLabel::kImpassable);
      }))
    return;

  // One cell more than the reach: a blocked cell whose corner is within reach must count.
  const int radius = int(std::ceil(box_reach_cells)) + 1;
  // Each cell's distance along its row to the nearest blocked cell, capped past the radius: a
  // disk around a cell holds a blocked cell when, in some row dy of it, that distance is within
  // the disk's half-width there.
  const auto far = std::uint16_t(radius + 1);
  std::vector<std::uint16_t> along_row(grid.cells(), far);
  for (int row = 0; row < grid.height; ++row) {
    std::uint16_t* distance = along_row.data() + grid.index(0, row);
    const CellState* state = classes.state.data() + grid.index(0, row);
    std::uint16_t since = far;
    for (int column = 0; column < grid.width; ++column) {
      since =
          state[column] == CellState::kBlocked ? 0 : std::uint16_t(std::min<int>(since + 1, far));
      distance[column] = since;
    }
    since = far;
    for (int column = grid.width - 1; column >= 0; --column) {
      since =
          state[column] == CellState::kBlocked ? 0 : std::uint16_t(std::min<int>(since + 1, far));
      distance[column] = std::min(distance[column], since);
    }
  }
  std::vector<int> half_width(std::size_t(2 * radius + 1));
  for (int dy = -radius; dy <= radius; ++dy)
    half_width[std::size_t(dy + radius)] =
        int(std::floor(std::sqrt(double(radius * radius - dy * dy))));

  // Row by row, every column at once (the compiler vectorises the comparisons), and only rows
  // that hold a too-narrow cell.
  // 16-bit like the distances, so that the comparisons pack into vector lanes unconverted.
  std::vector<std::uint16_t> near_blocked(std::size_t(grid.width));
  for (int row = 0; row < grid.height; ++row) {
    const std::size_t first = grid.index(0, row);
    bool any = false;
    for (int column = 0; column < grid.width && !any; ++column)
      any = too_narrow(first + std::size_t(column));
    if (!any) continue;
    std::fill(near_blocked.begin(), near_blocked.end(), std::uint16_t{0});
    for (int dy = -radius; dy <= radius; ++dy) {
      if (row + dy < 0 || row + dy >= grid.height) continue;
      const std::uint16_t* distance = along_row.data() + grid.index(0, row + dy);
      const auto half = std::uint16_t(half_width[std::size_t(dy + radius)]);
      std::uint16_t* near = near_blocked.data();
      for (int column = 0; column < grid.width; ++column)
        near[column] |= std::uint16_t(distance[column] <= half);
    }
    for (int column = 0; column < grid.width; ++column) {
      const std::size_t cell = first + std::size_t(column);
      if (near_blocked[std::size_t(column)] || !too_narrow(cell)) continue;
      map.labels[cell] = std::uint8_t(CellLabel::kUnknown);
      map.reasons[cell] = std::uint8_t(CellReason::kUnseenAround);
    }
  }
}

}  // namespace clearway::detail
