#pragma once

// Ground that no plane took in: a paving that bends or rises gently between two fitted planes
// leaves its returns a few centimetres off both, in no plane at all, and the map had no ground
// there (docs/ALGORITHM.md, "Ground no plane took in").

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <vector>

#include "clearway/scan.h"
#include "clearway/segmentation/scan_analysis.h"
#include "ground_triangles.h"

namespace clearway::detail {

struct GroundContinuationLimits {
  // A cell is flat when no return in it stands between this and `clear_height` above its lowest
  // one: nothing rises above ground noise within the robot's band. No step from one
  // return to the next along a line rises more than this either [m].
  float flatness = 0.04F;
  float clear_height = 1.5F;
  // Nor within this of the cell: a low box's face, grazed, is centimetres from its top (the
  // reach of facesOfTallObstacles() in cell_classes.cpp) [m].
  float clear_reach = 0.1F;
  // From one return to the next along a line the ground rises at most by `noise` plus the
  // drivable slope over the distance between them [m, m/m] ...
  float noise = 0.02F;
  float slope = 1.0F;
  // ... and never farther than this from the plane it continues [m].
  float off_plane = 0.1F;
};

struct ContinuedGround {
  std::vector<std::int32_t> ground_of;  // per point, its ground plane or -1
  std::vector<bool> continued;  // per point, true where continueGround added it; empty: none
};

// `ground_of` (per point, its ground plane or -1) with the returns that continue the ground added
// to the plane they continue: walking each scan line both ways from a ground return, the next
// returns that are in no plane, lie in a flat cell with no ground return of its own, rise gently
// from the last ground return and are no farther from it than `max_gap_squared(point)` allows;
// then, unless the lines are a multi-beam frame's rings, across the lines `pairing` pairs, from
// each ground return to its partner on the next line (forward over the pairs, then back), each
// line walked along again from what it took in.
// `plane_heights`: per plane its map height (h0, hx, hy), NaN for planes that are not ground.
ContinuedGround continueGround(std::vector<std::int32_t> ground_of, const Scan& scan,
                               const LinePairing& pairing,
                               const std::vector<std::int32_t>& point_plane,
                               const std::vector<Eigen::Vector3f>& mapped,
                               const std::vector<Eigen::Vector2i>& cell_of, const MapGrid& grid,
                               const std::vector<Eigen::Vector3d>& plane_heights,
                               const GroundContinuationLimits& limits,
                               const std::function<double(std::size_t)>& max_gap_squared);

}  // namespace clearway::detail
