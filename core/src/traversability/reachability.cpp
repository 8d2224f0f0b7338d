// Where the robot stands and where it can get to: a search over (cell, orientation) states from
// the robot's own pose. Moves are straight, forward or back along the heading (within 7.5 deg,
// up to 8 cells, the box fitting at every cell crossed: motion_primitives.h), never sideways, and
// turns on the spot to the next tried orientation where the box fits in both. Turning by one step
// of the tried orientations (15 deg by default) sweeps the box's corners at most R (1 - cos(step /
// 2)) beyond the two boxes (6 mm for the LMF), well inside the half cell of margin green cells
// keep.

#include "clearway/traversability/reachability.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "cell_classes.h"
#include "clearway/traversability/traversability_map.h"
#include "motion_primitives.h"
#include "reachability_search.h"

namespace clearway {
namespace {

constexpr double kPi = std::numbers::pi;

// Offsets of the scanner on the robot tried when no pose places the robot [m].
constexpr double kMountSearchStep = 0.1;
// One blocking return inside the box outweighs this many unobserved cells under it.
constexpr std::size_t kBlockingWeight = 1000;
// The robot's place found by the search is kept to this [m].
constexpr double kPoseQuantum = 1e-9;

double wrapHalfTurn(double yaw) {
  yaw = std::fmod(yaw, kPi);
  return yaw < 0 ? yaw + kPi : yaw;
}

}  // namespace

RobotPose robotPoseOnMap(const ScanAnalysis& analysis, const RobotParams& robot,
                         const std::vector<double>& yaws) {
  if (analysis.robot_from_scanner) {
    // The robot's origin and heading as the scanner saw them, carried into the map frame.
    const Eigen::Isometry3d map_from_robot =
        analysis.map_from_scanner * analysis.robot_from_scanner->inverse();
    const Eigen::Vector3d origin = map_from_robot.translation();
    const Eigen::Vector3d forward = map_from_robot.linear() * Eigen::Vector3d::UnitX();
    return {origin.x(), origin.y(), std::atan2(forward.y(), forward.x())};
  }
  // Without a recorded pose the scanner's foot (the map origin) is all that is known: the
  // scanner is somewhere on the robot and the robot stands where its box fits. Tried: the
  // mounting's offset first, then every offset that keeps the foot inside the box, in every
  // orientation. The box with the fewest blocking returns wins, then the one standing most on
  // observed ground (a scanner that sees one hemisphere leaves the floor behind it unknown, and a
  // wall may stand there), then the nearest to the mounting.
  const double half_length = robot.length / 2, half_width = robot.width / 2;
  const double resolution = analysis.inputs.grid.resolution;
  const double window = 2 * std::hypot(half_length, half_width) +
                        std::hypot(robot.mount_x, robot.mount_y) + resolution;
  const int side = 2 * int(std::ceil(window / resolution)) + 1;
  const int centre_cell = side / 2;
  std::vector<std::uint16_t> blocking(std::size_t(side) * std::size_t(side), 0);
  auto cellOf = [&](double x, double y) {
    return Eigen::Vector2i(int(std::floor(x / resolution)) + centre_cell,
                           int(std::floor(y / resolution)) + centre_cell);
  };
  auto addBlocking = [&](double x, double y) {
    const Eigen::Vector2i c = cellOf(x, y);
    if (c.x() < 0 || c.y() < 0 || c.x() >= side || c.y() >= side) return;
    std::uint16_t& count = blocking[std::size_t(c.y()) * std::size_t(side) + std::size_t(c.x())];
    if (count < std::numeric_limits<std::uint16_t>::max()) ++count;
  };
  for (const MapObstacle& o : analysis.inputs.obstacles)
    if (o.height > robot.max_step && o.height < robot.height) addBlocking(o.x, o.y);
  // Where a beam went down through the ground's level over unobserved ground, the floor ends:
  // that weighs as a blocking return. Counted as unobserved floor, it let the box of a scanner on
  // a ledge overhang the drop beside it, and the robot's own place, ground seen or not, showed the
  // drop traversable (4-16 false cells: a scanner 0.15-0.45 m from a platform's edge, the
  // stairwell's side floor in a random sweep; tests/unit/engine/floor_crossings_test.cpp).
  for (const FloorCrossing& crossing : analysis.inputs.floor_crossings)
    addBlocking(crossing.x, crossing.y);
  const MapGrid& grid = analysis.inputs.grid;
  const std::vector<std::int16_t>& ground_plane = analysis.inputs.ground_plane;
  // The robot stands on a level it can drive on: ground of another level under the box (a
  // pallet's top a little higher than its step) weighs as a blocking return. Counted as ground, a
  // box with the scanner's foot at its corner was placed over a 0.12 m pallet's top, and the
  // robot's own place, ground seen or not, showed the pallet's corner traversable (55 cells,
  // scripts/random-sweep: the garage tilted 37 deg, a 0.98 x 1.44 m robot).
  std::vector<std::uint8_t> other_level(analysis.planes.planes.size(), 1);
  for (const int plane : detail::reachableGround(analysis, robot.max_step))
    other_level[std::size_t(plane)] = 0;
  // What a sample of the box at map position (x, y) costs: its blocking returns, another level's
  // ground, and whether the ground there is unobserved.
  auto sampleCost = [&](double x, double y) {
    std::size_t cost = 0;
    const Eigen::Vector2i cell = cellOf(x, y);
    if (cell.x() >= 0 && cell.y() >= 0 && cell.x() < side && cell.y() < side)
      cost += kBlockingWeight *
              blocking[std::size_t(cell.y()) * std::size_t(side) + std::size_t(cell.x())];
    const Eigen::Vector2i map_cell = grid.cellOf(x, y);
    if (!grid.inside(map_cell.x(), map_cell.y())) return cost + 1;
    const int plane = ground_plane[grid.index(map_cell.x(), map_cell.y())];
    if (plane < 0) return cost + 1;
    return cost + (other_level[std::size_t(plane)] ? kBlockingWeight : 0);
  };
  // The box is sampled at the centres of a lattice `resolution` apart in its own frame.
  int samples_along = 0, samples_across = 0;
  for (double u = -half_length + resolution / 2; u < half_length; u += resolution)
    ++samples_along;
  for (double v = -half_width + resolution / 2; v < half_width; v += resolution)
    ++samples_across;
  auto blockedInside = [&](const RobotPose& pose) {
    const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
    std::size_t cost = 0;
    for (int i = 0; i < samples_along; ++i)
      for (int j = 0; j < samples_across; ++j) {
        const double u = -half_length + (i + 0.5) * resolution;
        const double v = -half_width + (j + 0.5) * resolution;
        cost += sampleCost(pose.x + c * u - s * v, pose.y + s * u + c * v);
      }
    return cost;
  };
  // The scanner at (mount_x, mount_y) of the robot's frame, the robot turned by yaw.
  auto poseFor = [&](double yaw, double mount_x, double mount_y) {
    const double c = std::cos(yaw), s = std::sin(yaw);
    return RobotPose{-(c * mount_x - s * mount_y), -(s * mount_x + c * mount_y), yaw};
  };
  std::vector<double> headings = {-robot.mount_yaw_deg * kPi / 180.0};
  headings.insert(headings.end(), yaws.begin(), yaws.end());
  RobotPose best = poseFor(headings.front(), robot.mount_x, robot.mount_y);
  std::size_t fewest = blockedInside(best);
  double best_shift = 0.0;
  // The offsets tried are a whole number of lattice steps apart (kMountSearchStep or more): in one
  // heading every box's samples are then points of one lattice, the box at offset (a, b) covering
  // its points (i - a k, j - b k). Each lattice point is costed once, and a box's cost is the sum
  // over a rectangle of them (a summed-area table).
  const int lattice_steps = std::max(1, int(std::ceil(kMountSearchStep / resolution - 1e-9)));
  const double step = lattice_steps * resolution;
  const int offsets_along = int(std::floor(2 * half_length / step + 1e-9)) + 1;
  const int offsets_across = int(std::floor(2 * half_width / step + 1e-9)) + 1;
  const int low_along = -(offsets_along - 1) * lattice_steps;
  const int low_across = -(offsets_across - 1) * lattice_steps;
  const int lattice_along = samples_along - low_along;  // lattice points along u
  const int lattice_across = samples_across - low_across;
  std::vector<std::size_t> table(std::size_t(lattice_along + 1) * std::size_t(lattice_across + 1));
  auto at = [&](int m, int n) -> std::size_t& {
    return table[std::size_t(m) * std::size_t(lattice_across + 1) + std::size_t(n)];
  };
  for (const double yaw : headings) {
    if (fewest == 0) break;
    const double c = std::cos(yaw), s = std::sin(yaw);
    // at(m, n): the cost of lattice points [0, m) x [0, n) (indices from low_along, low_across).
    for (int m = 0; m < lattice_along; ++m)
      for (int n = 0; n < lattice_across; ++n) {
        const double u = (m + low_along + 0.5) * resolution;
        const double v = (n + low_across + 0.5) * resolution;
        at(m + 1, n + 1) =
            sampleCost(c * u - s * v, s * u + c * v) + at(m, n + 1) + at(m + 1, n) - at(m, n);
      }
    for (int a = 0; a < offsets_along && fewest > 0; ++a)
      for (int b = 0; b < offsets_across && fewest > 0; ++b) {
        // Sample i of the box at offset a lies at u - dx = (i - a k + 1/2) res: lattice index
        // i - a k - low_along.
        const int first_m = (offsets_along - 1 - a) * lattice_steps;
        const int first_n = (offsets_across - 1 - b) * lattice_steps;
        const std::size_t inside = at(first_m + samples_along, first_n + samples_across) -
                                   at(first_m, first_n + samples_across) -
                                   at(first_m + samples_along, first_n) + at(first_m, first_n);
        const double dx = -half_length + a * step, dy = -half_width + b * step;
        const double shift = std::hypot(dx - robot.mount_x, dy - robot.mount_y);
        if (inside < fewest || (inside == fewest && shift < best_shift)) {
          fewest = inside;
          best = poseFor(yaw, dx, dy);
          best_shift = shift;
        }
      }
  }
  // To the nanometre: the rounding of the offsets' sums must not decide which cells a box edge
  // that falls on a cell boundary takes.
  auto snap = [](double metres) { return std::round(metres / kPoseQuantum) * kPoseQuantum; };
  return {snap(best.x), snap(best.y), best.yaw};
}

namespace detail {

std::vector<std::vector<int>> turnNeighbours(const std::vector<double>& yaws) {
  const int count = int(yaws.size());
  std::vector<int> order(std::size_t(count), 0);
  for (int k = 0; k < count; ++k)
    order[std::size_t(k)] = k;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return wrapHalfTurn(yaws[std::size_t(a)]) < wrapHalfTurn(yaws[std::size_t(b)]);
  });
  std::vector<std::vector<int>> neighbours(static_cast<std::size_t>(count));
  if (count < 2) return neighbours;
  for (int i = 0; i < count; ++i) {
    const int here = order[std::size_t(i)];
    neighbours[std::size_t(here)].push_back(order[std::size_t((i + 1) % count)]);
    if (count > 2)
      neighbours[std::size_t(here)].push_back(order[std::size_t((i + count - 1) % count)]);
  }
  return neighbours;
}

namespace {

// Up to this many orientations, a cell's poses are the bits of one word.
constexpr std::size_t kMaskBits = 64;

// Records, for every cell the search looked at (`looked`), the fit of each of its orientations,
// and makes the robot's own pose valid: its box stands there even where the cell-centred tests,
// half a cell off its exact position, touch something just outside it.
void keepLookedAtFits(TraversabilityMap& map, const std::vector<std::uint8_t>& pose_fits,
                      const std::vector<std::uint8_t>& looked, std::size_t start_cell) {
  const std::size_t orientations = map.yaws.size();
  for (std::size_t cell = 0; cell < looked.size(); ++cell)
    if (looked[cell])
      std::copy_n(pose_fits.data() + cell * orientations, orientations, map.pose_fit.fitsOf(cell));
  std::uint8_t& start_fit = map.pose_fit.fitsOf(start_cell)[std::size_t(map.robot_orientation)];
  if (start_fit == std::uint8_t(PoseFit::kBlocked)) start_fit = std::uint8_t(PoseFit::kCareful);
  map.reachable_cells = std::size_t(std::count(map.reach.begin(), map.reach.end(), 1));
}

// The search a word at a time: bit b of a cell's masks is the b-th orientation by angle, so
// turning to the next tried orientation on either side is a one-bit rotation, and a move is
// driven in every orientation that drives it with one AND per cell it crosses. The same states
// are reached and the same cells looked at as one pose at a time.
void searchByMasks(TraversabilityMap& map, const std::vector<std::uint8_t>& pose_fits,
                   const std::vector<std::uint32_t>& may_enter, const Eigen::Vector2i& start) {
  using Mask = std::uint64_t;
  const MapGrid& grid = map.grid;
  const std::size_t orientations = map.yaws.size();
  std::vector<int> by_angle(orientations);  // orientation of each bit
  for (std::size_t k = 0; k < orientations; ++k)
    by_angle[k] = int(k);
  std::stable_sort(by_angle.begin(), by_angle.end(), [&](int a, int b) {
    return wrapHalfTurn(map.yaws[std::size_t(a)]) < wrapHalfTurn(map.yaws[std::size_t(b)]);
  });
  std::vector<int> bit_of(orientations);
  for (std::size_t b = 0; b < orientations; ++b)
    bit_of[std::size_t(by_angle[b])] = int(b);
  const Mask all = orientations == kMaskBits ? ~Mask{0} : (Mask{1} << orientations) - 1;
  // The orientations one turn away from any of `m`'s (none with a single orientation).
  auto turned = [&](Mask m) -> Mask {
    if (orientations < 2) return 0;
    const Mask up = ((m << 1) | (m >> (orientations - 1))) & all;
    const Mask down = ((m >> 1) | (m << (orientations - 1))) & all;
    return up | down;
  };
  // `m` and every orientation of `open` it can turn to, step by step.
  auto closeTurns = [&](Mask m, Mask open) {
    for (;;) {
      const Mask grown = m | (turned(m) & open);
      if (grown == m) return m;
      m = grown;
    }
  };
  const std::size_t cells = grid.cells();
  // The orientations the box fits in, per cell (none outside the cells the search may enter).
  std::vector<Mask> open(cells, 0), reached(cells, 0);
  for (const std::uint32_t cell : may_enter) {
    const std::uint8_t* fits = pose_fits.data() + std::size_t(cell) * orientations;
    Mask m = 0;
    for (std::size_t k = 0; k < orientations; ++k)
      if (fits[k] != std::uint8_t(PoseFit::kBlocked)) m |= Mask{1} << bit_of[k];
    open[cell] = m;
  }
  // The cells the search looked at: their fits are kept.
  std::vector<std::uint8_t> looked(cells, 0);
  // The orientations that drive each move, and every move's crossed cells as steps in the cell
  // array, one list after the other.
  const MotionPrimitives primitives = motionPrimitives(map.yaws);
  std::vector<Mask> drives(primitives.moves.size(), 0);
  for (std::size_t k = 0; k < orientations; ++k)
    for (const int move : primitives.of_orientation[k])
      drives[std::size_t(move)] |= Mask{1} << bit_of[k];
  std::vector<std::ptrdiff_t> crossed_steps;
  std::vector<std::size_t> first_step(primitives.moves.size() + 1, 0);
  for (std::size_t p = 0; p < primitives.moves.size(); ++p) {
    for (const MotionPrimitive::Crossed& step : primitives.moves[p].crossed)
      crossed_steps.push_back(std::ptrdiff_t(step.dy) * grid.width + step.dx);
    first_step[p + 1] = crossed_steps.size();
  }
  // The robot stands there, in its own heading even where the tests say its box does not fit.
  // Where its heading is a guess, it may stand in any orientation its box fits in there.
  const std::size_t start_cell = grid.index(start.x(), start.y());
  const Mask start_bit = Mask{1} << bit_of[std::size_t(map.robot_orientation)];
  const Mask start_mask = map.robot_heading_known ? start_bit : start_bit | open[start_cell];
  open[start_cell] |= start_bit;
  looked[start_cell] = 1;
  reached[start_cell] = closeTurns(start_mask, open[start_cell]);
  // What each cell has handed on: a cell is handed on again only with the orientations it
  // reached since, so every (cell, orientation, move) is driven once.
  std::vector<Mask> handed(cells, 0);
  // Cells whose reached orientations grew and are still to be handed on, first in first out (a
  // cell is then rarely handed on twice), each queued at most once at a time.
  std::vector<std::uint32_t> work = {std::uint32_t(start_cell)};
  std::vector<std::uint8_t> in_work(cells, 0);
  in_work[start_cell] = 1;
  // The arrays every crossed cell reads and writes, as plain pointers: the compiler cannot tell a
  // vector's data from its bookkeeping, and reloaded them at every cell.
  const Mask* const open_of = open.data();
  std::uint8_t* const looked_of = looked.data();
  std::uint8_t* const reach_of = map.reach.data();
  for (std::size_t head = 0; head < work.size(); ++head) {
    const std::size_t cell = work[head];
    in_work[cell] = 0;
    const Mask here = reached[cell] & ~handed[cell];
    handed[cell] |= here;
    reach_of[cell] = 1;
    const int row = int(cell / std::size_t(grid.width));
    const int column = int(cell - std::size_t(row) * std::size_t(grid.width));
    const bool inner = column >= kLongestMoveCells && row >= kLongestMoveCells &&
                       column + kLongestMoveCells < grid.width &&
                       row + kLongestMoveCells < grid.height;
    for (std::size_t p = 0; p < primitives.moves.size(); ++p) {
      Mask m = here & drives[p];
      if (!m) continue;
      // Away from the map's edge (the moves are at most kLongestMoveCells long) every crossed
      // cell is inside; near it, a move stops where it would leave the map.
      const std::ptrdiff_t* const first = crossed_steps.data() + first_step[p];
      const std::ptrdiff_t* const last = crossed_steps.data() + first_step[p + 1];
      std::size_t next = cell;
      if (inner) {
        // A cell crossed is looked at: reached on the way, or (below) where the move stopped.
        for (const std::ptrdiff_t* step = first; step != last; ++step) {
          next = std::size_t(std::ptrdiff_t(cell) + *step);
          m &= open_of[next];
          if (!m) {
            looked_of[next] = 1;
            break;
          }
          reach_of[next] = 1;  // the box stands there on its way
        }
      } else {
        const MotionPrimitive::Crossed* crossed = primitives.moves[p].crossed.data();
        for (const std::ptrdiff_t* step = first; step != last; ++step, ++crossed) {
          if (!grid.inside(column + crossed->dx, row + crossed->dy)) {
            m = 0;
            break;
          }
          next = std::size_t(std::ptrdiff_t(cell) + *step);
          looked_of[next] = 1;
          m &= open_of[next];
          if (!m) break;
          reach_of[next] = 1;
        }
      }
      const Mask arriving = m & ~reached[next];
      if (!arriving) continue;
      reached[next] = closeTurns(reached[next] | arriving, open[next]);
      if (!in_work[next]) {
        in_work[next] = 1;
        work.push_back(std::uint32_t(next));
      }
    }
  }
  for (std::size_t cell = 0; cell < cells; ++cell)
    looked[cell] |= reach_of[cell];
  keepLookedAtFits(map, pose_fits, looked, start_cell);
}

}  // namespace

std::vector<std::uint32_t> cellsTheSearchMayEnter(
    const TraversabilityMap& map, const std::vector<std::uint8_t>& fit_orientation) {
  const MapGrid& grid = map.grid;
  const Eigen::Vector2i start = grid.cellOf(map.robot_pose.x, map.robot_pose.y);
  if (map.yaws.empty() || map.robot_orientation < 0 || !grid.inside(start.x(), start.y()))
    return {};
  // Breadth first over cells; the robot's own cell is entered whatever its tests say.
  std::vector<std::uint8_t> queued(grid.cells(), 0);
  std::vector<std::uint32_t> cells = {std::uint32_t(grid.index(start.x(), start.y()))};
  queued[cells.front()] = 1;
  for (std::size_t next = 0; next < cells.size(); ++next) {
    const std::size_t cell = cells[next];
    const int row = int(cell / std::size_t(grid.width));
    const int column = int(cell - std::size_t(row) * std::size_t(grid.width));
    for (int n = 0; n < 8; ++n) {
      const int c = column + kNeighbourColumns[n], r = row + kNeighbourRows[n];
      if (!grid.inside(c, r)) continue;
      const std::size_t neighbour = grid.index(c, r);
      if (queued[neighbour] || fit_orientation[neighbour] == kNoOrientation) continue;
      queued[neighbour] = 1;
      cells.push_back(std::uint32_t(neighbour));
    }
  }
  return cells;
}

void searchReachable(TraversabilityMap& map, const std::vector<std::uint8_t>& pose_fits,
                     const std::vector<std::uint32_t>& may_enter) {
  const MapGrid& grid = map.grid;
  const std::size_t orientations = map.yaws.size();
  map.reach.assign(grid.cells(), 0);
  map.pose_fit = MetPoseFits(grid.cells(), orientations);
  map.reachable_cells = 0;
  const Eigen::Vector2i start = grid.cellOf(map.robot_pose.x, map.robot_pose.y);
  if (orientations == 0 || map.robot_orientation < 0 || !grid.inside(start.x(), start.y())) return;
  if (orientations <= kMaskBits) {
    searchByMasks(map, pose_fits, may_enter, start);
    return;
  }
  const std::vector<std::vector<int>> turns = turnNeighbours(map.yaws);
  const MotionPrimitives primitives = motionPrimitives(map.yaws);
  // Breadth first over states, each queued once; a state's fit is its own, so the order of the
  // search changes nothing. States travel with their column, row and orientation: no division to
  // recover them.
  struct Pose {
    int column, row, k;
  };
  std::vector<std::uint8_t> looked(grid.cells(), 0);
  std::vector<std::uint8_t> queued(grid.cells() * orientations, 0);
  std::vector<Pose> queue;
  // Whether the box fits at (column, row) in orientation k (always at the robot's own pose, see
  // below); the cell is looked at.
  const std::size_t own_state =
      grid.index(start.x(), start.y()) * orientations + std::size_t(map.robot_orientation);
  auto fits = [&](int column, int row, int k) {
    const std::size_t cell = grid.index(column, row);
    looked[cell] = 1;
    const std::size_t state = cell * orientations + std::size_t(k);
    return state == own_state || pose_fits[state] != std::uint8_t(PoseFit::kBlocked);
  };
  auto stand = [&](int column, int row, int k) {
    const std::size_t state = grid.index(column, row) * orientations + std::size_t(k);
    if (queued[state]) return;
    queued[state] = 1;
    queue.push_back({column, row, k});
  };
  // The robot stands there, in its own heading even where the tests say its box does not fit.
  // Where its heading is a guess, it may stand in any orientation its box fits in there.
  for (int k = 0; k < int(orientations); ++k)
    if (fits(start.x(), start.y(), k) && (k == map.robot_orientation || !map.robot_heading_known))
      stand(start.x(), start.y(), k);
  for (std::size_t next = 0; next < queue.size(); ++next) {
    const Pose pose = queue[next];
    map.reach[grid.index(pose.column, pose.row)] = 1;
    for (const int index : primitives.of_orientation[std::size_t(pose.k)]) {
      const MotionPrimitive& move = primitives.moves[std::size_t(index)];
      bool fits_all = true;
      for (const MotionPrimitive::Crossed& step : move.crossed) {
        const int c = pose.column + step.dx, r = pose.row + step.dy;
        if (!grid.inside(c, r) || !fits(c, r, pose.k)) {
          fits_all = false;
          break;
        }
        map.reach[grid.index(c, r)] = 1;  // the box stands there on its way
      }
      if (fits_all) stand(pose.column + move.dx, pose.row + move.dy, pose.k);
    }
    for (int other : turns[std::size_t(pose.k)])
      if (fits(pose.column, pose.row, other)) stand(pose.column, pose.row, other);
  }
  keepLookedAtFits(map, pose_fits, looked, grid.index(start.x(), start.y()));
}

}  // namespace detail

}  // namespace clearway
