#pragma once

// The robot-height part of the map: what each cell is before the robot's box is moved over it.

#include <cstdint>
#include <vector>

#include "clearway/segmentation/scan_analysis.h"
#include "clearway/traversability/ground_density.h"
#include "clearway/traversability/traversability_map.h"

namespace clearway::detail {

enum class CellState : std::uint8_t { kUnknown, kGround, kLowObstacle, kBlocked };

// Whether the robot's box may stand over a cell of this state: ground, or a low obstacle on it.
inline bool isFree(CellState state) {
  return state == CellState::kGround || state == CellState::kLowObstacle;
}

struct CellClasses {
  std::vector<CellState> state;
  std::vector<CellReason> reason;
  // Blocked only by measured points (their exact positions are known), not by unknown areas,
  // other levels or steps: the narrow-passage check can look at the points themselves.
  std::vector<std::uint8_t> blocked_by_points_only;
  // Blocking points per cell, as ranges into xs/ys (CSR layout).
  std::vector<std::uint32_t> point_start;
  std::vector<float> xs, ys;
  std::vector<int> accepted_ground;
  // 1 on free cells whose ground samples are too far apart to rule out an obstacle taller than
  // the robot's step between them (MapInputs::ground_spacing against the step), where the
  // robot's band above the ground lies in an overhang's shadow, or in the wedge a blocking point
  // may reach into towards the next line (MapInputs::sweep_neighbours), or where the band was
  // above the scanner's view (`above_view`).
  std::vector<std::uint8_t> sparse;
  // 1 on free cells whose band up to the robot's height no beam rose through (view_band.h).
  std::vector<std::uint8_t> above_view;
  // 1 on the cells made ground because the robot stands there (classifyCells' `own_place`), seen
  // or not; empty without it.
  std::vector<std::uint8_t> own_place;
  // Where the scanner's rays start, on the map [m].
  Eigen::Vector2d viewpoint = Eigen::Vector2d::Zero();
};

// Ground planes reachable from the reference through contacts no higher than the robot's step
// (MapInputs::contacts): the levels the robot can drive on.
std::vector<int> reachableGround(const ScanAnalysis& analysis, double max_step);

// The same classes with every sparse cell blocked (reason kSparse, not by points).
CellClasses withSparseBlocked(const CellClasses& classes);

// With `own_place`, the robot stands there: returns inside its box are its own body and are
// dropped, and the cells under it (to the half cell the coarse test adds) are ground. Unobserved
// floor around it stays unknown: a scanner that sees one hemisphere cannot tell the floor its body
// hid from a wall behind it. The walks along beams and chords run on up to `threads` threads (the
// result does not depend on it).
CellClasses classifyCells(const ScanAnalysis& analysis, const RobotParams& robot,
                          const MapParams& params, const RobotPose* own_place = nullptr,
                          int threads = 1);

}  // namespace clearway::detail
