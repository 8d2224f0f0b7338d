#pragma once

// The exact Euclidean distance from every cell of a grid to the nearest cell that blocks, for the
// footprint tests' clearances (footprints.h).

#include <cstdint>
#include <vector>

namespace clearway::detail {

// Distance [cells] from each cell's centre to the nearest centre of a cell whose `free` byte is 0,
// the outside of the grid blocking as a ring of such cells around it. Row-major, width * height.
// Exact (two separable passes: the distance within each column, then the lower envelope of one
// parabola per cell along each row), in time linear in the cells.
std::vector<float> distanceToBlocked(const std::vector<std::uint8_t>& free, int width, int height);

}  // namespace clearway::detail
