// The footprint tests' clearances come from an exact distance field: on random grids of several
// densities and shapes it must give, to float rounding, the distance a search over every blocking
// cell (and the ring of blocking cells around the grid) finds.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "../../../core/src/traversability/distance_field.h"

namespace clearway::detail {
namespace {

float bruteForceDistance(const std::vector<std::uint8_t>& free, int width, int height, int column,
                         int row) {
  double best = std::numeric_limits<double>::infinity();
  for (int r = -1; r <= height; ++r)
    for (int c = -1; c <= width; ++c) {
      const bool outside = r < 0 || c < 0 || r >= height || c >= width;
      if (outside || !free[std::size_t(r) * std::size_t(width) + std::size_t(c)])
        best = std::min(best, std::hypot(double(c - column), double(r - row)));
    }
  return float(best);
}

TEST(DistanceField, IsTheExactDistanceToTheNearestBlockingCell) {
  std::mt19937 random(11);
  int compared = 0;
  for (const double blocking : {0.0, 0.002, 0.05, 0.4, 1.0})
    for (const auto& [width, height] : {std::pair{1, 1}, {1, 37}, {41, 1}, {23, 19}, {60, 45}}) {
      std::bernoulli_distribution blocks(blocking);
      std::vector<std::uint8_t> free(std::size_t(width) * std::size_t(height));
      for (std::uint8_t& cell : free)
        cell = blocks(random) ? 0 : 1;
      const std::vector<float> distance = distanceToBlocked(free, width, height);
      ASSERT_EQ(distance.size(), free.size());
      for (int row = 0; row < height; ++row)
        for (int column = 0; column < width; ++column) {
          const float expected = bruteForceDistance(free, width, height, column, row);
          ASSERT_NEAR(distance[std::size_t(row) * std::size_t(width) + std::size_t(column)],
                      expected, 1e-5F * expected)
              << width << " x " << height << " at (" << column << ", " << row << "), " << blocking
              << " blocking";
          ++compared;
        }
    }
  EXPECT_EQ(compared, 5 * (1 + 37 + 41 + 23 * 19 + 60 * 45));
}

TEST(DistanceField, BlockingCellsAreAtZeroAndAnOpenGridIsBoundedByItsEdge) {
  // A 9 x 5 grid, all free but its corner cell (0, 0): the outside blocks, so the centre cell is 3
  // from the ring of blocking cells around the grid (rows -1 and 5), not infinitely far.
  std::vector<std::uint8_t> free(45, 1);
  free[0] = 0;
  const std::vector<float> distance = distanceToBlocked(free, 9, 5);
  EXPECT_EQ(distance[0], 0.0F);
  EXPECT_FLOAT_EQ(distance[2 * 9 + 4], 3.0F);
  EXPECT_FLOAT_EQ(distance[1 * 9 + 1], std::sqrt(2.0F));  // diagonal to the blocking cell
  EXPECT_FLOAT_EQ(distance[2 * 9 + 2], std::sqrt(8.0F));  // nearer (0, 0) than the edges (3)
}

}  // namespace
}  // namespace clearway::detail
