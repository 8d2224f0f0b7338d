// Where the robot stands and where it can get to: a search over (cell, orientation) states from
// the robot's own pose. Moves are one cell to any of the eight neighbours keeping the heading
// (the box fits at both ends, 5 cm apart) and turns on the spot to the next tried orientation
// where the box fits in both. Turning by one step of the tried orientations (15 deg by default)
// sweeps the box's corners at most R (1 - cos(step / 2)) beyond the two boxes (6 mm for the LMF),
// well inside the half cell of margin green cells keep.

#include "clearway/traversability/reachability.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <queue>

#include "../segmentation/parallel.h"
#include "clearway/traversability/traversability_map.h"
#include "reachability_search.h"

namespace clearway {
namespace {

constexpr double kPi = std::numbers::pi;

// Path costs: orange (careful) cells cost this many times a green one, so the path keeps its
// margin where it can; each turn step costs as much as this much straight driving [m].
constexpr double kCarefulCostFactor = 3.0;
constexpr double kTurnCost = 0.05;
// Rings of the reachability search smaller than this are tested on one thread (handing a few
// states to the pool costs more than testing them).
constexpr std::size_t kParallelRing = 64;
// Offsets of the scanner on the robot tried when no pose places the robot [m].
constexpr double kMountSearchStep = 0.1;
// One blocking return inside the box outweighs this many unobserved cells under it.
constexpr std::size_t kBlockingWeight = 1000;
// A path keeps a pose at least every this many cells, besides every turn.
constexpr int kPathPoseEvery = 10;

constexpr int kNeighbourColumns[8] = {1, -1, 0, 0, 1, 1, -1, -1};
constexpr int kNeighbourRows[8] = {0, 0, 1, -1, 1, -1, 1, -1};

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
  for (const MapObstacle& o : analysis.inputs.obstacles) {
    if (o.height <= robot.max_step || o.height >= robot.height) continue;
    const Eigen::Vector2i c = cellOf(o.x, o.y);
    if (c.x() < 0 || c.y() < 0 || c.x() >= side || c.y() >= side) continue;
    std::uint16_t& count = blocking[std::size_t(c.y()) * std::size_t(side) + std::size_t(c.x())];
    if (count < std::numeric_limits<std::uint16_t>::max()) ++count;
  }
  const MapGrid& grid = analysis.inputs.grid;
  const std::vector<std::int16_t>& ground_plane = analysis.inputs.ground_plane;
  auto blockedInside = [&](const RobotPose& pose) {
    const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
    std::size_t blocked = 0, unobserved = 0;
    for (double u = -half_length + resolution / 2; u < half_length; u += resolution)
      for (double v = -half_width + resolution / 2; v < half_width; v += resolution) {
        const double x = pose.x + c * u - s * v, y = pose.y + s * u + c * v;
        const Eigen::Vector2i cell = cellOf(x, y);
        if (cell.x() >= 0 && cell.y() >= 0 && cell.x() < side && cell.y() < side)
          blocked += blocking[std::size_t(cell.y()) * std::size_t(side) + std::size_t(cell.x())];
        const Eigen::Vector2i map_cell = grid.cellOf(x, y);
        unobserved += !grid.inside(map_cell.x(), map_cell.y()) ||
                      ground_plane[grid.index(map_cell.x(), map_cell.y())] < 0;
      }
    return blocked * kBlockingWeight + unobserved;
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
  const double step = std::max(kMountSearchStep, resolution);
  for (double yaw : headings)
    for (double dx = -half_length; dx <= half_length + 1e-9 && fewest > 0; dx += step)
      for (double dy = -half_width; dy <= half_width + 1e-9 && fewest > 0; dy += step) {
        const RobotPose pose = poseFor(yaw, dx, dy);
        const std::size_t inside = blockedInside(pose);
        const double shift = std::hypot(dx - robot.mount_x, dy - robot.mount_y);
        if (inside < fewest || (inside == fewest && shift < best_shift)) {
          fewest = inside;
          best = pose;
          best_shift = shift;
        }
      }
  return best;
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

void searchReachable(TraversabilityMap& map, const std::function<PoseFit(int, int, int)>& fitAt,
                     int threads) {
  const MapGrid& grid = map.grid;
  const std::size_t orientations = map.yaws.size();
  map.reach.assign(grid.cells(), 0);
  map.pose_fit.assign(grid.cells() * orientations, std::uint8_t(PoseFit::kUntested));
  map.reachable_cells = 0;
  const Eigen::Vector2i start = grid.cellOf(map.robot_pose.x, map.robot_pose.y);
  if (orientations == 0 || map.robot_orientation < 0 || !grid.inside(start.x(), start.y())) return;
  const std::vector<std::vector<int>> turns = turnNeighbours(map.yaws);
  // Breadth first, one ring of states at a time: the fits of a ring's new states are tested in
  // parallel (each state once, each into its own memo slot), then the ones that fit are entered.
  // States travel with their column, row and orientation: no division to recover them.
  struct Pose {
    int column, row, k;
  };
  std::vector<std::uint8_t> queued(grid.cells() * orientations, 0);
  auto stateOf = [&](int column, int row, int k) {
    return grid.index(column, row) * orientations + std::size_t(k);
  };
  auto fitOf = [&](const Pose& pose) { return fitAt(pose.column, pose.row, pose.k); };
  const Pose first{start.x(), start.y(), map.robot_orientation};
  const std::size_t first_state = stateOf(first.column, first.row, first.k);
  queued[first_state] = 1;
  // The robot stands there: its own pose is valid even where the cell-centred tests, half a cell
  // off its exact position, touch something just outside its box.
  map.pose_fit[first_state] = std::uint8_t(fitOf(first));
  if (map.pose_fit[first_state] == std::uint8_t(PoseFit::kBlocked))
    map.pose_fit[first_state] = std::uint8_t(PoseFit::kCareful);
  std::vector<Pose> ring = {first}, candidates;
  while (!ring.empty()) {
    for (const Pose& pose : ring) {
      const std::size_t cell = grid.index(pose.column, pose.row);
      if (!map.reach[cell]) {
        map.reach[cell] = 1;
        ++map.reachable_cells;
      }
    }
    candidates.clear();
    for (const Pose& pose : ring) {
      auto propose = [&](int column, int row, int k) {
        std::uint8_t& seen = queued[stateOf(column, row, k)];
        if (seen) return;
        seen = 1;
        candidates.push_back({column, row, k});
      };
      for (int n = 0; n < 8; ++n) {
        const int c = pose.column + kNeighbourColumns[n], r = pose.row + kNeighbourRows[n];
        if (grid.inside(c, r)) propose(c, r, pose.k);
      }
      for (int other : turns[std::size_t(pose.k)])
        propose(pose.column, pose.row, other);
    }
    const int workers = candidates.size() >= kParallelRing ? threads : 1;
    parallelChunks(
        candidates.size(), workers, [&](std::size_t begin, std::size_t end, std::size_t) {
          for (std::size_t i = begin; i < end; ++i) {
            const Pose& pose = candidates[i];
            map.pose_fit[stateOf(pose.column, pose.row, pose.k)] = std::uint8_t(fitOf(pose));
          }
        });
    ring.clear();
    for (const Pose& pose : candidates)
      if (map.pose_fit[stateOf(pose.column, pose.row, pose.k)] != std::uint8_t(PoseFit::kBlocked))
        ring.push_back(pose);
  }
}

}  // namespace detail

GoalResult planPath(const TraversabilityMap& map, double goal_x, double goal_y) {
  GoalResult result;
  const MapGrid& grid = map.grid;
  const Eigen::Vector2i goal = grid.cellOf(goal_x, goal_y);
  if (!grid.inside(goal.x(), goal.y())) {
    result.reason = "the goal is outside the map";
    return result;
  }
  const std::size_t goal_cell = grid.index(goal.x(), goal.y());
  const CellLabel label = CellLabel(map.labels[goal_cell]);
  const bool fits = label == CellLabel::kTraversable || label == CellLabel::kCareful ||
                    label == CellLabel::kObstacle;
  if (map.reach.empty() || map.robot_orientation < 0) {
    result.reason = "the robot's own place is not on the map";
    return result;
  }
  if (!map.reach[goal_cell]) {
    if (!fits) {
      const std::string why(reasonName(CellReason(map.reasons[goal_cell])));
      result.reason = "the robot does not fit at the goal (" + std::string(labelName(label)) +
                      (why.empty() ? "" : ": " + why) + ")";
    } else {
      result.reason = "the robot fits at the goal but cannot get there from where it stands";
    }
    return result;
  }

  const std::size_t orientations = map.yaws.size();
  const std::vector<std::vector<int>> turns = detail::turnNeighbours(map.yaws);
  const Eigen::Vector2i start = grid.cellOf(map.robot_pose.x, map.robot_pose.y);
  const std::size_t states = grid.cells() * orientations;
  std::vector<double> cost(states, std::numeric_limits<double>::infinity());
  std::vector<std::int64_t> previous(states, -1);
  using Entry = std::pair<double, std::size_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  const std::size_t first =
      grid.index(start.x(), start.y()) * orientations + std::size_t(map.robot_orientation);
  // A*: the straight-line distance to the goal never overestimates (green costs 1 per metre, turns
  // cost more than nothing), so the first time the goal leaves the queue its path is cheapest.
  const Eigen::Vector2d goal_centre = grid.centre(goal.x(), goal.y());
  auto remaining = [&](int column, int row) {
    return (grid.centre(column, row) - goal_centre).norm();
  };
  cost[first] = 0.0;
  queue.push({remaining(start.x(), start.y()), first});
  auto passable = [&](std::size_t state) {
    const auto f = PoseFit(map.pose_fit[state]);
    return f == PoseFit::kClear || f == PoseFit::kCareful;
  };
  std::int64_t reached = -1;
  while (!queue.empty()) {
    const auto [priority, state] = queue.top();
    queue.pop();
    const std::size_t cell = state / orientations;
    const int k = int(state - cell * orientations);
    const int row = int(cell / std::size_t(grid.width));
    const int column = int(cell - std::size_t(row) * std::size_t(grid.width));
    const double here_cost = cost[state];
    const double here_remaining = remaining(column, row);
    if (priority > here_cost + here_remaining + 1e-9) continue;  // a stale entry
    if (cell == goal_cell) {
      reached = std::int64_t(state);
      break;
    }
    // The heuristic is worked out only for states that get queued (a square root each).
    auto relax = [&](std::size_t next, auto&& next_remaining, double step) {
      if (!passable(next)) return;
      const double factor =
          PoseFit(map.pose_fit[next]) == PoseFit::kCareful ? kCarefulCostFactor : 1.0;
      const double next_cost = here_cost + step * factor;
      if (next_cost < cost[next]) {
        cost[next] = next_cost;
        previous[next] = std::int64_t(state);
        queue.push({next_cost + next_remaining(), next});
      }
    };
    for (int n = 0; n < 8; ++n) {
      const int c = column + kNeighbourColumns[n], r = row + kNeighbourRows[n];
      if (!grid.inside(c, r)) continue;
      const double step = grid.resolution * (n < 4 ? 1.0 : std::numbers::sqrt2);
      relax(
          grid.index(c, r) * orientations + std::size_t(k), [&] { return remaining(c, r); }, step);
    }
    for (int other : turns[std::size_t(k)])
      relax(
          cell * orientations + std::size_t(other), [&] { return here_remaining; }, kTurnCost);
  }
  if (reached < 0) {
    result.reason = "no path found to the goal";
    return result;
  }
  std::vector<std::size_t> chain;
  for (std::int64_t s = reached; s >= 0; s = previous[std::size_t(s)])
    chain.push_back(std::size_t(s));
  std::reverse(chain.begin(), chain.end());
  result.reachable = true;
  int since_kept = 0;
  for (std::size_t i = 0; i < chain.size(); ++i) {
    const std::size_t cell = chain[i] / orientations;
    const int k = int(chain[i] % orientations);
    const int column = int(cell % std::size_t(grid.width)),
              row = int(cell / std::size_t(grid.width));
    if (i > 0) {
      const std::size_t before = chain[i - 1] / orientations;
      if (before != cell) {
        const int dc = column - int(before % std::size_t(grid.width));
        const int dr = row - int(before / std::size_t(grid.width));
        result.length_m += grid.resolution * std::hypot(double(dc), double(dr));
      }
    }
    const bool turn = i + 1 < chain.size() && int(chain[i + 1] % orientations) != k;
    const bool turned = i > 0 && int(chain[i - 1] % orientations) != k;
    if (i == 0 || i + 1 == chain.size() || turn || turned || ++since_kept >= kPathPoseEvery) {
      const Eigen::Vector2d centre = grid.centre(column, row);
      result.path.push_back({centre.x(), centre.y(), map.yaws[std::size_t(k)] * 180.0 / kPi});
      since_kept = 0;
    }
  }
  return result;
}

}  // namespace clearway
