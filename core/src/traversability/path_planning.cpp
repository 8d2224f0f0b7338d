// "Can it get there?": A* over the reachability search's states and moves on the fits it kept
// (docs/ALGORITHM.md, "The robot's own place and where it can get").

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "clearway/traversability/reachability.h"
#include "clearway/traversability/traversability_map.h"
#include "motion_primitives.h"
#include "reachability_search.h"

namespace clearway {

namespace {

constexpr double kPi = std::numbers::pi;

// Path costs: orange (careful) cells cost this many times a green one, so the path keeps its
// margin where it can; each turn step costs as much as this much straight driving [m].
constexpr double kCarefulCostFactor = 3.0;
constexpr double kTurnCost = 0.05;
// A path keeps a pose at least every this many cells of driving, besides every turn.
constexpr int kPathPoseEvery = 10;

using detail::kNeighbourColumns;
using detail::kNeighbourRows;

// The A* queue of (priority, state), ordered like std::priority_queue with std::greater on the
// pair (equal priorities by state), so states leave in exactly that order. Priorities fall into
// buckets `width` wide: only the lowest bucket is kept as a heap (a few dozen entries), the later
// ones are plain lists heaped when their turn comes. An entry below the lowest bucket (rounding)
// joins its heap, where it still leaves first.
class QueueOfStates {
 public:
  struct Entry {
    double priority;
    std::size_t state;
    // std::*_heap keep the largest on top: the greater entry is the lesser here.
    bool operator<(const Entry& other) const {
      return priority > other.priority || (priority == other.priority && state > other.state);
    }
  };
  explicit QueueOfStates(double width) : width_(width) {}
  bool empty() const { return size_ == 0; }
  void push(Entry entry) {
    ++size_;
    const std::size_t bucket = bucketOf(entry.priority);
    if (bucket <= current_) {
      lowest_.push_back(entry);
      std::push_heap(lowest_.begin(), lowest_.end());
      return;
    }
    if (bucket >= later_.size()) later_.resize(bucket + 1);
    later_[bucket].push_back(entry);
  }
  Entry pop() {
    while (lowest_.empty()) {
      ++current_;
      if (current_ < later_.size()) {
        lowest_.swap(later_[current_]);
        std::make_heap(lowest_.begin(), lowest_.end());
      }
    }
    std::pop_heap(lowest_.begin(), lowest_.end());
    const Entry top = lowest_.back();
    lowest_.pop_back();
    --size_;
    return top;
  }

 private:
  std::size_t bucketOf(double priority) const {
    return std::size_t(std::max(0.0, priority / width_));
  }
  double width_;
  std::size_t current_ = 0;
  std::size_t size_ = 0;
  std::vector<Entry> lowest_;
  std::vector<std::vector<Entry>> later_;
};

// The cost of a move so far, cell by cell: each cell crossed costs the step into it as a single
// eight-neighbour move would, times its factor. Where the line runs through a corner, going on
// costs the step times the dearer of the two cells; ending in the second costs its own step.
struct MoveCost {
  double through = 0.0;  // to the last cell crossed, going on
  double before_pair = 0.0, step = 0.0, factor = 0.0;
  // Enters `crossed` (its factor `f`); returns the cost of ending there.
  double enter(const detail::MotionPrimitive::Crossed& crossed, double resolution, double f) {
    if (!crossed.tie) {
      before_pair = through;
      step = crossed.step * resolution;
      factor = f;
      through += step * f;
      return through;
    }
    factor = std::max(factor, f);
    through = before_pair + step * factor;
    return before_pair + crossed.step * resolution * f;
  }
};

// Per dense cell, the cheapest cost to the goal's dense cell over 8-neighbour moves, a move costing
// its length times the cheapest fitting pose's factor in the cell it enters (infinite where the
// goal cannot be reached). Dijkstra from the goal.
std::vector<double> cheapestToGoal(const MapGrid& grid, const std::vector<std::int32_t>& dense_cell,
                                   const std::vector<std::size_t>& cell_of,
                                   const std::vector<double>& factor, std::size_t orientations,
                                   std::size_t goal) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  std::vector<double> cheapest_factor(cell_of.size(), kInfinity);
  for (std::size_t d = 0; d < cell_of.size(); ++d)
    for (std::size_t k = 0; k < orientations; ++k)
      if (const double f = factor[d * orientations + k]; f > 0.0)
        cheapest_factor[d] = std::min(cheapest_factor[d], f);
  std::vector<double> remaining(cell_of.size(), kInfinity);
  // Buckets a sixteenth of a cell wide, as the A*'s.
  QueueOfStates queue(grid.resolution / 16);
  remaining[goal] = 0.0;
  queue.push({0.0, goal});
  while (!queue.empty()) {
    const auto [to_goal, dense] = queue.pop();
    if (to_goal > remaining[dense]) continue;  // a stale entry
    const std::size_t cell = cell_of[dense];
    const int row = int(cell / std::size_t(grid.width));
    const int column = int(cell - std::size_t(row) * std::size_t(grid.width));
    for (int n = 0; n < 8; ++n) {
      const int c = column + kNeighbourColumns[n], r = row + kNeighbourRows[n];
      if (!grid.inside(c, r)) continue;
      const std::int32_t from = dense_cell[grid.index(c, r)];
      if (from < 0) continue;
      // From the neighbour into this cell.
      const double step = grid.resolution * (n < 4 ? 1.0 : std::numbers::sqrt2);
      const double through = to_goal + step * cheapest_factor[dense];
      if (through < remaining[std::size_t(from)]) {
        remaining[std::size_t(from)] = through;
        queue.push({through, std::size_t(from)});
      }
    }
  }
  return remaining;
}

}  // namespace

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
  const bool fits = robotFits(label);
  if (map.reach.empty() || map.robot_orientation < 0) {
    result.reason = "the robot's own place is not on the map";
    return result;
  }
  if (!map.reach[goal_cell]) {
    if (label == CellLabel::kUnknown) {
      // Nothing seen there says it could stand there: "(unknown)" read as the answer's state.
      result.reason = "the goal was not seen well enough to tell whether the robot can stand there";
    } else if (label == CellLabel::kStairs) {
      result.reason = "the goal is on stairs: the way there is planned over level ground only";
    } else if (!fits) {
      const std::string why(reasonName(CellReason(map.reasons[goal_cell])));
      result.reason = "the robot does not fit at the goal (" + std::string(labelName(label)) +
                      (why.empty() ? "" : ": " + why) + ")";
    } else {
      result.reason = "the robot fits at the goal but cannot get there from where it stands";
      if (!map.reach_limit.empty()) result.reason += " (" + map.reach_limit + ")";
    }
    return result;
  }

  const std::size_t orientations = map.yaws.size();
  const std::vector<std::vector<int>> turns = detail::turnNeighbours(map.yaws);
  const detail::MotionPrimitives primitives = detail::motionPrimitives(map.yaws);
  const Eigen::Vector2i start = grid.cellOf(map.robot_pose.x, map.robot_pose.y);
  // A path only ever enters poses the reachability search found the box fits in, all in reachable
  // cells: the search numbers those cells densely, in map order, so its arrays stay small enough
  // for the caches (a few per cent of the map's states) and its queue keeps the same order.
  std::vector<std::int32_t> dense_cell(grid.cells(), -1);
  std::vector<std::size_t> cell_of;  // the map cell of each dense cell
  cell_of.reserve(map.reachable_cells);
  for (std::size_t cell = 0; cell < grid.cells(); ++cell)
    if (map.reach[cell]) {
      dense_cell[cell] = std::int32_t(cell_of.size());
      cell_of.push_back(cell);
    }
  const std::size_t states = cell_of.size() * orientations;
  // The step cost factor of each pose: 1 green, kCarefulCostFactor orange, 0 where it cannot go.
  std::vector<double> factor(states, 0.0);
  for (std::size_t d = 0; d < cell_of.size(); ++d)
    for (std::size_t k = 0; k < orientations; ++k) {
      const PoseFit fit = map.pose_fit.at(cell_of[d], k);
      factor[d * orientations + k] = fit == PoseFit::kClear     ? 1.0
                                     : fit == PoseFit::kCareful ? kCarefulCostFactor
                                                                : 0.0;
    }
  std::vector<double> cost(states, std::numeric_limits<double>::infinity());
  std::vector<std::int32_t> previous(states, -1);
  // Buckets a sixteenth of a cell of driving wide.
  QueueOfStates queue(grid.resolution / 16);
  const std::int32_t start_cell =
      grid.inside(start.x(), start.y()) ? dense_cell[grid.index(start.x(), start.y())] : -1;
  if (start_cell < 0) {
    result.reason = "the robot's own place is not on the map";
    return result;
  }
  // A* with, as the heuristic, the cheapest way to the goal over the reachable cells when every
  // cell is entered at its cheapest fitting pose, turns are free and the box may move to any of
  // the eight neighbours: it never overestimates (a move costs what its cells cost as single
  // steps, and the search only adds turns and the poses' constraints) and it is consistent, so
  // the first time the goal leaves the queue its path is cheapest. Unlike the straight line, it
  // knows where the doors are: across a winding route the straight line sent the search over most
  // of the map's poses.
  const std::vector<double> remaining = cheapestToGoal(
      grid, dense_cell, cell_of, factor, orientations, std::size_t(dense_cell[goal_cell]));
  if (!std::isfinite(remaining[std::size_t(start_cell)])) {
    result.reason = "no path found to the goal";
    return result;
  }
  // The robot's own pose; where its heading is a guess, every orientation its box fits in there.
  for (std::size_t k = 0; k < orientations; ++k) {
    const std::size_t first = std::size_t(start_cell) * orientations + k;
    if (int(k) != map.robot_orientation && (map.robot_heading_known || factor[first] == 0.0))
      continue;
    cost[first] = 0.0;
    queue.push({remaining[std::size_t(start_cell)], first});
  }
  std::int64_t reached = -1;
  while (!queue.empty()) {
    // A named copy of the state: clang 14 lets no lambda (relax below) capture a structured
    // binding.
    const auto [priority, popped] = queue.pop();
    const std::size_t state = popped;
    const std::size_t dense = state / orientations;
    const int k = int(state - dense * orientations);
    const std::size_t cell = cell_of[dense];
    const int row = int(cell / std::size_t(grid.width));
    const int column = int(cell - std::size_t(row) * std::size_t(grid.width));
    const double here_cost = cost[state];
    const double here_remaining = remaining[dense];
    if (priority > here_cost + here_remaining + 1e-9) continue;  // a stale entry
    if (cell == goal_cell) {
      reached = std::int64_t(state);
      break;
    }
    auto relax = [&](std::size_t next, double next_remaining, double added_cost) {
      if (factor[next] == 0.0 || !std::isfinite(next_remaining)) return;
      const double next_cost = here_cost + added_cost;
      if (next_cost < cost[next]) {
        cost[next] = next_cost;
        previous[next] = std::int32_t(state);
        queue.push({next_cost + next_remaining, next});
      }
    };
    // The moves along the heading: every cell crossed must be reachable with the box fitting in
    // this orientation; a move that crosses the goal's cell ends there.
    for (const int index : primitives.of_orientation[std::size_t(k)]) {
      MoveCost move_cost;
      for (const detail::MotionPrimitive::Crossed& crossed :
           primitives.moves[std::size_t(index)].crossed) {
        const int c = column + crossed.dx, r = row + crossed.dy;
        if (!grid.inside(c, r)) break;
        const std::int32_t next_cell = dense_cell[grid.index(c, r)];
        if (next_cell < 0) break;  // not reachable: no pose there fits
        const std::size_t next = std::size_t(next_cell) * orientations + std::size_t(k);
        if (factor[next] == 0.0) break;
        const double to_here = move_cost.enter(crossed, grid.resolution, factor[next]);
        if (cell_of[std::size_t(next_cell)] == goal_cell) {
          relax(next, 0.0, to_here);
          break;
        }
        if (&crossed == &primitives.moves[std::size_t(index)].crossed.back())
          relax(next, remaining[std::size_t(next_cell)], move_cost.through);
      }
    }
    for (int other : turns[std::size_t(k)]) {
      const std::size_t turned_state = dense * orientations + std::size_t(other);
      relax(turned_state, here_remaining, kTurnCost * factor[turned_state]);
    }
  }
  if (reached < 0) {
    result.reason = "no path found to the goal";
    return result;
  }
  std::vector<std::size_t> chain;  // map states: cell * orientations + k
  for (std::int64_t s = reached; s >= 0; s = previous[std::size_t(s)])
    chain.push_back(cell_of[std::size_t(s) / orientations] * orientations +
                    std::size_t(s) % orientations);
  std::reverse(chain.begin(), chain.end());
  result.reachable = true;
  result.cost = cost[std::size_t(reached)];
  int cells_since_kept = 0;
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
        const double step = grid.resolution * std::hypot(double(dc), double(dr));
        result.length_m += step;
        // (A map built by hand for a test may carry labels and fits but no reasons.)
        const auto reason =
            cell < map.reasons.size() ? CellReason(map.reasons[cell]) : CellReason::kNone;
        if (reason == CellReason::kSparse || reason == CellReason::kAboveView)
          result.unvouched_m += step;
        cells_since_kept += std::max(std::abs(dc), std::abs(dr));
      }
    }
    const bool turn = i + 1 < chain.size() && int(chain[i + 1] % orientations) != k;
    const bool turned = i > 0 && int(chain[i - 1] % orientations) != k;
    if (i == 0 || i + 1 == chain.size() || turn || turned || cells_since_kept >= kPathPoseEvery) {
      cells_since_kept = 0;
      const Eigen::Vector2d centre = grid.centre(column, row);
      result.path.push_back({centre.x(), centre.y(), map.yaws[std::size_t(k)] * 180.0 / kPi});
    }
  }
  return result;
}

}  // namespace clearway
