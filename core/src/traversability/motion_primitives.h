#pragma once

// The moves of the reachability search: in each tried orientation, straight moves along the
// robot's heading (forward or back), not sideways. A tracked or wheeled base does not slide: a
// robot wider than it is long must not be taken sideways through a door narrower than its width.

#include <numbers>
#include <vector>

namespace clearway::detail {

// A move of the box's centre from one cell's centre to another's, (dx, dy) cells, in a heading
// within kMoveSlipRad of the move's direction. The box must fit at every cell the move crosses:
// `crossed` lists them in order, the end last; where the line passes through a cell corner both
// cells are listed (the second of such a pair has `tie` set).
struct MotionPrimitive {
  int dx = 0, dy = 0;
  struct Crossed {
    int dx = 0, dy = 0;  // from the move's start [cells]
    bool tie = false;    // the line runs through the corner between this cell and the previous
    // The step into this cell from the cell crossed before (before the pair, for a tie's cells)
    // as an eight-neighbour move: 1 or sqrt 2 cells. A move costs what its cells cost as single
    // steps, so the planner's heuristic (eight-neighbour moves) never overestimates.
    double step = 0.0;
  };
  std::vector<Crossed> crossed;
  double length = 0.0;  // [cells]
};

// How far a move's direction may lie from the heading [rad]: half the default turn step (15 deg).
// The robot turns that little to drive the move, a turn whose sweep stays well inside the half
// cell of margin green cells keep; a door is never crossed sideways.
inline constexpr double kMoveSlipRad = 7.5 * std::numbers::pi / 180.0;
// The longest move, in cells along x or y. With 4, every direction lies within 7.02 deg of one
// of the moves (the widest gap between lattice directions is 0 to atan(1/4)).
inline constexpr int kLongestMoveCells = 8;

struct MotionPrimitives {
  std::vector<MotionPrimitive> moves;
  // Per tried orientation, the moves it drives (indices into `moves`; forward and back).
  std::vector<std::vector<int>> of_orientation;
};

// The moves of every orientation of `yaws` [rad], forward and back: along the lattice direction
// nearest the heading, and along the shortest within kMoveSlipRad of it on either side (so that
// the robot can edge sideways as it drives, as a real one does by steering a little: a robot
// standing at the edge of what the scanner saw, its own heading a guess, got nowhere without).
MotionPrimitives motionPrimitives(const std::vector<double>& yaws);

}  // namespace clearway::detail
