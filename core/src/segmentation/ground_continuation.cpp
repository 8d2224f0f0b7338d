#include "ground_continuation.h"

#include <cmath>
#include <limits>

namespace clearway::detail {
namespace {

constexpr float kNone = std::numeric_limits<float>::infinity();

constexpr std::uint32_t kOutside = 0xFFFFFFFFU;

// Each point's cell index, kOutside for invalid points and points outside the grid.
std::vector<std::uint32_t> cellIndices(const Scan& scan,
                                       const std::vector<Eigen::Vector2i>& cell_of,
                                       const MapGrid& grid) {
  std::vector<std::uint32_t> index(scan.size(), kOutside);
  for (std::size_t i = 0; i < scan.size(); ++i)
    if (scan.isValid(i) && grid.inside(cell_of[i].x(), cell_of[i].y()))
      index[i] = std::uint32_t(grid.index(cell_of[i].x(), cell_of[i].y()));
  return index;
}

// Cells that may hold ground no plane took in: no ground return of their own, no plane's return
// (a stair's tread, a wall's foot) on their lowest one, and, in the cell or within `clear_reach`
// of it, nothing standing in the robot's band over it and nothing below it by more than ground
// noise: ground is level there. The lower returns on a low box's face lie centimetres from its
// top, and are that box; the top of a kerb lies centimetres from the ground at its foot, and
// taken in as ground it would bring the level above it within a step of the one below.
std::vector<std::uint8_t> flatCells(const std::vector<std::int32_t>& ground_of,
                                    const std::vector<std::int32_t>& point_plane,
                                    const std::vector<Eigen::Vector3f>& mapped,
                                    const std::vector<std::uint32_t>& cell_index,
                                    const MapGrid& grid, const GroundContinuationLimits& limits) {
  // Per cell: its lowest return (any), its lowest return in no ground plane, and the highest
  // return in the robot's band over the lowest.
  std::vector<float> lowest(grid.cells(), kNone), lowest_free(grid.cells(), kNone);
  std::vector<float> highest(grid.cells(), -kNone);
  std::vector<std::uint8_t> flat(grid.cells(), 0);
  for (std::size_t i = 0; i < cell_index.size(); ++i) {
    const std::uint32_t cell = cell_index[i];
    if (cell == kOutside) continue;
    const float z = mapped[i].z();
    lowest[cell] = std::min(lowest[cell], z);
    if (ground_of[i] < 0)
      lowest_free[cell] = std::min(lowest_free[cell], z);
    else
      flat[cell] = 2;  // holds ground: never a candidate
  }
  for (std::size_t i = 0; i < cell_index.size(); ++i) {
    const std::uint32_t cell = cell_index[i];
    if (cell == kOutside) continue;
    const float z = mapped[i].z(), above = z - lowest[cell];
    if (above < limits.clear_height) highest[cell] = std::max(highest[cell], z);
    if (ground_of[i] < 0 && point_plane[i] >= 0 && above <= limits.flatness) flat[cell] = 2;
  }
  // The cells within clear_reach of anywhere in a cell: one more than the reach in cells, as the
  // returns lie anywhere in theirs.
  const int reach = int(std::ceil(limits.clear_reach / grid.resolution - 1e-6)) + 1;
  for (int row = 0; row < grid.height; ++row)
    for (int column = 0; column < grid.width; ++column) {
      const std::size_t cell = grid.index(column, row);
      if (flat[cell] == 2 || lowest_free[cell] == kNone) {
        flat[cell] = 0;
        continue;
      }
      const float floor = lowest_free[cell];
      bool clear = true;
      for (int r = std::max(0, row - reach); clear && r <= std::min(grid.height - 1, row + reach);
           ++r)
        for (int c = std::max(0, column - reach);
             clear && c <= std::min(grid.width - 1, column + reach); ++c) {
          const std::size_t near = grid.index(c, r);
          clear = !(highest[near] > floor + limits.flatness &&
                    highest[near] < floor + limits.clear_height) &&
                  !(lowest[near] < floor - limits.flatness);
        }
      flat[cell] = clear;
    }
  return flat;
}

}  // namespace

ContinuedGround continueGround(std::vector<std::int32_t> ground_of, const Scan& scan,
                               const std::vector<std::int32_t>& point_plane,
                               const std::vector<Eigen::Vector3f>& mapped,
                               const std::vector<Eigen::Vector2i>& cell_of, const MapGrid& grid,
                               const std::vector<Eigen::Vector3d>& plane_heights,
                               const GroundContinuationLimits& limits,
                               const std::function<double(std::size_t)>& max_gap_squared) {
  const std::vector<std::uint32_t> cell_index = cellIndices(scan, cell_of, grid);
  const std::vector<std::uint8_t> flat =
      flatCells(ground_of, point_plane, mapped, cell_index, grid, limits);
  auto planeZ = [&](std::int32_t plane, const Eigen::Vector3f& p) {
    if (plane < 0 || std::size_t(plane) >= plane_heights.size())
      return std::numeric_limits<double>::quiet_NaN();
    const Eigen::Vector3d& h = plane_heights[std::size_t(plane)];
    return h.x() + h.y() * double(p.x()) + h.z() * double(p.y());
  };
  // Whether return `i` continues the ground from the ground return `from` before it on its line.
  auto continues = [&](std::size_t i, std::size_t from) {
    if (point_plane[i] >= 0 || !flat[cell_index[i]]) return false;
    const Eigen::Vector3f& p = mapped[i];
    const Eigen::Vector3f& q = mapped[from];
    const double gap_squared = double((p.head<2>() - q.head<2>()).squaredNorm());
    if (gap_squared > max_gap_squared(i)) return false;
    const double rise = std::abs(double(p.z() - q.z()));
    if (rise > limits.flatness || rise > limits.noise + limits.slope * std::sqrt(gap_squared))
      return false;
    const double plane_z = planeZ(ground_of[from], p);
    return std::isfinite(plane_z) && std::abs(double(p.z()) - plane_z) <= limits.off_plane;
  };
  std::vector<bool> continued(ground_of.size(), false);
  // Both ways along each line: a stretch between two planes is reached from either end.
  auto walk = [&](std::size_t first, std::size_t end, std::ptrdiff_t direction) {
    std::size_t last = std::numeric_limits<std::size_t>::max();
    for (std::size_t k = 0; k < end - first; ++k) {
      const std::size_t i = direction > 0 ? first + k : end - 1 - k;
      if (cell_index[i] == kOutside) continue;
      if (ground_of[i] >= 0) {
        last = i;
      } else if (last != std::numeric_limits<std::size_t>::max() && continues(i, last)) {
        ground_of[i] = ground_of[last];
        continued[i] = true;
        last = i;
      }
    }
  };
  for (const ScanLine& line : scan.lines) {
    walk(line.first, line.first + line.count, +1);
    walk(line.first, line.first + line.count, -1);
  }
  return {std::move(ground_of), std::move(continued)};
}

}  // namespace clearway::detail
