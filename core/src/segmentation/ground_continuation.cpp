#include "ground_continuation.h"

#include <algorithm>
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
class FlatCells {
 public:
  FlatCells(const std::vector<std::int32_t>& ground_of,
            const std::vector<std::int32_t>& point_plane,
            const std::vector<Eigen::Vector3f>& mapped,
            const std::vector<std::uint32_t>& cell_index, const MapGrid& grid,
            const GroundContinuationLimits& limits)
      : grid_(grid),
        limits_(limits),
        lowest_(grid.cells(), kNone),
        lowest_free_(grid.cells(), kNone),
        highest_(grid.cells(), -kNone),
        lowest_near_(grid.cells(), std::numeric_limits<float>::quiet_NaN()),
        state_(grid.cells(), kUnknown),
        // The cells within clear_reach of anywhere in a cell: one more than the reach in cells,
        // as the returns lie anywhere in theirs.
        reach_(int(std::ceil(limits.clear_reach / grid.resolution - 1e-6)) + 1) {
    // Per cell: its lowest return (any), its lowest return in no ground plane, and the highest
    // return in the robot's band over the lowest.
    for (std::size_t i = 0; i < cell_index.size(); ++i) {
      const std::uint32_t cell = cell_index[i];
      if (cell == kOutside) continue;
      const float z = mapped[i].z();
      lowest_[cell] = std::min(lowest_[cell], z);
      if (ground_of[i] < 0)
        lowest_free_[cell] = std::min(lowest_free_[cell], z);
      else
        state_[cell] = kNotFlat;  // holds ground: never a candidate
    }
    for (std::size_t i = 0; i < cell_index.size(); ++i) {
      const std::uint32_t cell = cell_index[i];
      if (cell == kOutside) continue;
      const float z = mapped[i].z(), above = z - lowest_[cell];
      if (above < limits.clear_height) highest_[cell] = std::max(highest_[cell], z);
      if (ground_of[i] < 0 && point_plane[i] >= 0 && above <= limits.flatness)
        state_[cell] = kNotFlat;
    }
  }

  // Whether nothing within `clear_reach` of `cell` lies lower than `z` by more than ground
  // noise: a return at `z` there is on the lowest surface around, not up an obstacle's face.
  bool lowestAround(std::uint32_t cell, float z) {
    if (std::isnan(lowest_near_[cell])) {
      float lowest = kNone;
      forCellsNear(cell, [&](std::size_t near) {
        lowest = std::min(lowest, lowest_[near]);
        return true;
      });
      lowest_near_[cell] = lowest;
    }
    return lowest_near_[cell] >= z - limits_.flatness;
  }

  // Asked only of the cells the walk reaches (most returns are in planes and never are).
  bool flat(std::uint32_t cell) {
    if (state_[cell] == kUnknown) state_[cell] = level(cell) ? kFlat : kNotFlat;
    return state_[cell] == kFlat;
  }

 private:
  static constexpr std::uint8_t kUnknown = 0, kFlat = 1, kNotFlat = 2;

  // Each cell within clear_reach of `cell`, to `visit`, until it returns false; whether none did.
  template <typename Visit>
  bool forCellsNear(std::uint32_t cell, Visit&& visit) const {
    const int row = int(cell / std::uint32_t(grid_.width)),
              column = int(cell % std::uint32_t(grid_.width));
    for (int r = std::max(0, row - reach_); r <= std::min(grid_.height - 1, row + reach_); ++r)
      for (int c = std::max(0, column - reach_); c <= std::min(grid_.width - 1, column + reach_);
           ++c)
        if (!visit(grid_.index(c, r))) return false;
    return true;
  }

  bool level(std::uint32_t cell) const {
    const float floor = lowest_free_[cell];
    if (floor == kNone) return false;
    return forCellsNear(cell, [&](std::size_t near) {
      return !(highest_[near] > floor + limits_.flatness &&
               highest_[near] < floor + limits_.clear_height) &&
             lowest_[near] >= floor - limits_.flatness;
    });
  }

  const MapGrid& grid_;
  const GroundContinuationLimits& limits_;
  std::vector<float> lowest_, lowest_free_, highest_;
  std::vector<float> lowest_near_;  // the lowest return within clear_reach; NaN: not asked yet
  std::vector<std::uint8_t> state_;
  int reach_;
};

}  // namespace

ContinuedGround continueGround(std::vector<std::int32_t> ground_of, const Scan& scan,
                               const LinePairing& pairing,
                               const std::vector<std::int32_t>& point_plane,
                               const std::vector<Eigen::Vector3f>& mapped,
                               const std::vector<Eigen::Vector2i>& cell_of, const MapGrid& grid,
                               const std::vector<Eigen::Vector3d>& plane_heights,
                               const GroundContinuationLimits& limits,
                               const std::function<double(std::size_t)>& max_gap_squared) {
  const std::vector<std::uint32_t> cell_index = cellIndices(scan, cell_of, grid);
  FlatCells cells(ground_of, point_plane, mapped, cell_index, grid, limits);
  auto planeZ = [&](std::int32_t plane, const Eigen::Vector3f& p) {
    if (plane < 0 || std::size_t(plane) >= plane_heights.size())
      return std::numeric_limits<double>::quiet_NaN();
    return heightOnPlane(plane_heights[std::size_t(plane)], double(p.x()), double(p.y()));
  };
  // Whether return `i` continues the ground from the ground return `from` before it on its line.
  auto continues = [&](std::size_t i, std::size_t from) {
    if (point_plane[i] >= 0 || !cells.flat(cell_index[i])) return false;
    const Eigen::Vector3f& p = mapped[i];
    const Eigen::Vector3f& q = mapped[from];
    // Only from ground on the lowest surface around it: a return of the floor's plane up an
    // obstacle's face (the plane's band holds a kerb's face where the plane, fitted over tilted
    // slabs, passes a few centimetres above the slab at its foot) does not carry the floor onto
    // what the obstacle stands beside (the outdoor kerb: 7 false cells when walked across lines).
    if (!cells.lowestAround(cell_index[from], q.z())) return false;
    const double rise = std::abs(double(p.z() - q.z()));
    if (rise > limits.flatness) return false;
    const double gap_squared = double((p.head<2>() - q.head<2>()).squaredNorm());
    if (rise > limits.noise + limits.slope * std::sqrt(gap_squared)) return false;
    if (gap_squared > max_gap_squared(i)) return false;
    const double plane_z = planeZ(ground_of[from], p);
    return std::isfinite(plane_z) && std::abs(double(p.z()) - plane_z) <= limits.off_plane;
  };
  std::vector<bool> continued(ground_of.size(), false);
  std::size_t taken = 0;
  auto take = [&](std::size_t i, std::size_t from) {
    ground_of[i] = ground_of[from];
    continued[i] = true;
    ++taken;
  };
  // None taken in (an indoor scan's ground is all planar): an empty mark, which every ground
  // triangle's join test reads as "none" without looking up its corners.
  auto finish = [&] {
    if (taken == 0) continued.clear();
    return ContinuedGround{std::move(ground_of), std::move(continued)};
  };
  // Both ways along each line: a stretch between two planes is reached from either end.
  auto walk = [&](std::size_t first, std::size_t end, std::ptrdiff_t direction) {
    std::size_t last = std::numeric_limits<std::size_t>::max();
    for (std::size_t k = 0; k < end - first; ++k) {
      const std::size_t i = direction > 0 ? first + k : end - 1 - k;
      if (cell_index[i] == kOutside) continue;
      if (ground_of[i] >= 0) {
        last = i;
      } else if (last != std::numeric_limits<std::size_t>::max() && continues(i, last)) {
        take(i, last);
        last = i;
      }
    }
  };
  auto walkBothWays = [&](const ScanLine& line) {
    walk(line.first, line.first + line.count, +1);
    walk(line.first, line.first + line.count, -1);
  };
  for (const ScanLine& line : scan.lines)
    walkBothWays(line);
  // Across the lines, as the ground triangles pair them: a nodding scanner's tilted fans cross
  // the floor at one range each, and a fan wholly off the plane (3DTK's walkway levelling out
  // beyond a 4.7 deg ramp, 0.05-0.15 m above the ramp's plane) has no ground return of its own
  // to walk from. A multi-beam frame's rings, metres apart on the road, are followed outward
  // before the planes are made (ring_ground.h).
  if (pairing.multiBeam()) return finish();
  std::vector<std::size_t> partners;
  // A return that may still be taken in: in no plane, not ground yet, on the map.
  auto open = [&](std::size_t i) {
    return point_plane[i] < 0 && ground_of[i] < 0 && cell_index[i] != kOutside;
  };
  auto across = [&](const ScanLine& from, const ScanLine& to) {
    if (from.count == 0 || to.count == 0) return;
    // Most lines' returns are all in planes or ground already: their partners are not wanted.
    bool any_open = false;
    for (std::size_t i = to.first; i < to.first + to.count && !any_open; ++i)
      any_open = open(i);
    if (!any_open) return;
    pairing.partners(to, from, partners);
    bool took = false;
    for (std::size_t k = 0; k < to.count; ++k) {
      const std::size_t i = to.first + k, last = partners[k];
      if (!open(i) || ground_of[last] < 0 || cell_index[last] == kOutside || !continues(i, last))
        continue;
      take(i, last);
      took = true;
    }
    if (took) walkBothWays(to);
  };
  for (std::size_t pair = 0; pair < pairing.pairs(); ++pair)
    across(pairing.before(pair), pairing.after(pair));
  for (std::size_t pair = pairing.pairs(); pair-- > 0;)
    across(pairing.after(pair), pairing.before(pair));
  return finish();
}

}  // namespace clearway::detail
