#include "motion_primitives.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <numeric>

namespace clearway::detail {
namespace {

// The angle between two directions as lines (modulo 180 deg), in [0, 90 deg].
double lineAngle(double a, double b) {
  double difference = std::fmod(std::abs(a - b), std::numbers::pi);
  return std::min(difference, std::numbers::pi - difference);
}

MotionPrimitive makeMove(int dx, int dy) {
  MotionPrimitive move;
  move.dx = dx;
  move.dy = dy;
  move.length = std::hypot(double(dx), double(dy));
  // One step along the major axis at a time; the minor coordinate is the line's, rounded, and
  // both cells where it falls half way.
  const int steps = std::max(std::abs(dx), std::abs(dy));
  int last_x = 0, last_y = 0;
  for (int i = 1; i <= steps; ++i) {
    // Twice the exact position, in whole numbers: (2 i dx / steps, 2 i dy / steps).
    const int twice_x = 2 * i * dx, twice_y = 2 * i * dy;
    auto rounded = [&](int twice, bool up) {
      // twice / (2 steps) rounded; on a half, down or up as asked.
      const int doubled_steps = 2 * steps;
      const int floor_value = int(std::floor(double(twice) / doubled_steps));
      const int remainder = twice - floor_value * doubled_steps;  // in [0, 2 steps)
      if (2 * remainder < doubled_steps) return floor_value;
      if (2 * remainder > doubled_steps) return floor_value + 1;
      return up ? floor_value + 1 : floor_value;
    };
    const bool half_x = (twice_x % (2 * steps) + 2 * steps) % (2 * steps) == steps;
    const bool half_y = (twice_y % (2 * steps) + 2 * steps) % (2 * steps) == steps;
    const int x = rounded(twice_x, false), y = rounded(twice_y, false);
    auto stepTo = [&](int to_x, int to_y) {
      return (to_x != last_x && to_y != last_y) ? std::numbers::sqrt2 : 1.0;
    };
    move.crossed.push_back({x, y, false, stepTo(x, y)});
    if (half_x || half_y) {
      const int other_x = rounded(twice_x, true), other_y = rounded(twice_y, true);
      move.crossed.push_back({other_x, other_y, true, stepTo(other_x, other_y)});
    }
    last_x = x;
    last_y = y;
  }
  return move;
}

}  // namespace

MotionPrimitives motionPrimitives(const std::vector<double>& yaws) {
  MotionPrimitives primitives;
  // Every direction of the lattice up to kLongestMoveCells, once (coprime steps).
  std::vector<std::array<int, 2>> directions;
  for (int dy = -kLongestMoveCells; dy <= kLongestMoveCells; ++dy)
    for (int dx = -kLongestMoveCells; dx <= kLongestMoveCells; ++dx)
      if (std::gcd(std::abs(dx), std::abs(dy)) == 1) directions.push_back({dx, dy});
  std::vector<int> index_of(directions.size(), -1);
  auto moveIndex = [&](std::size_t d) {
    if (index_of[d] < 0) {
      index_of[d] = int(primitives.moves.size());
      primitives.moves.push_back(makeMove(directions[d][0], directions[d][1]));
    }
    return index_of[d];
  };
  primitives.of_orientation.resize(yaws.size());
  for (std::size_t k = 0; k < yaws.size(); ++k) {
    // The direction nearest the heading, and the shortest within the slip on either side of it
    // (so that the robot can edge left and right as it drives), each forward and back.
    const double heading =
        std::fmod(std::fmod(yaws[k], std::numbers::pi) + std::numbers::pi, std::numbers::pi);
    std::size_t nearest = 0;
    double nearest_angle = std::numbers::pi;
    std::array<std::size_t, 2> shortest{directions.size(), directions.size()};  // right, left
    for (std::size_t d = 0; d < directions.size(); ++d) {
      const double direction = std::atan2(double(directions[d][1]), double(directions[d][0]));
      const double angle = lineAngle(direction, heading);
      if (angle < nearest_angle - 1e-12) {
        nearest_angle = angle;
        nearest = d;
      }
      if (angle > kMoveSlipRad + 1e-9 || angle < 1e-12) continue;
      // Which side of the heading's line the direction lies on (the line's own direction and
      // its reverse on the same side).
      const double cross = std::cos(heading) * double(directions[d][1]) -
                           std::sin(heading) * double(directions[d][0]);
      const bool forward = std::cos(heading) * double(directions[d][0]) +
                               std::sin(heading) * double(directions[d][1]) >
                           0;
      const std::size_t side = (cross > 0) == forward ? 1 : 0;
      auto steps = [&](std::size_t e) {
        return std::max(std::abs(directions[e][0]), std::abs(directions[e][1]));
      };
      std::size_t& best = shortest[side];
      if (best == directions.size() || steps(d) < steps(best) ||
          (steps(d) == steps(best) &&
           angle < lineAngle(std::atan2(double(directions[best][1]), double(directions[best][0])),
                             heading)))
        best = d;
    }
    std::vector<int>& moves = primitives.of_orientation[k];
    auto addLine = [&](std::size_t d) {
      // Forward and back: the direction and its reverse.
      for (std::size_t e = 0; e < directions.size(); ++e)
        if ((directions[e][0] == directions[d][0] && directions[e][1] == directions[d][1]) ||
            (directions[e][0] == -directions[d][0] && directions[e][1] == -directions[d][1])) {
          const int index = moveIndex(e);
          if (std::find(moves.begin(), moves.end(), index) == moves.end()) moves.push_back(index);
        }
    };
    addLine(nearest);
    for (const std::size_t d : shortest)
      if (d < directions.size()) addLine(d);
  }
  return primitives;
}

}  // namespace clearway::detail
