#pragma once

// A box a little taller than the robot's step, grazed by a scan line along one of its faces:
// the line's returns come down the face, and the last few, two to four centimetres up, lie in
// the floor plane's band and join the ground. The ground triangulated through them then reaches
// across the box's corner to the floor beyond, and the robot's box fitted there (the simulated
// garage's pallet at 80 lines: 1-2 careful cells over its corner). Such returns are the face,
// not the floor: they follow a higher return of their line closely, and each stands clearly
// above the plane it was put in.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "clearway/scan.h"

namespace clearway::detail {

struct FaceReturnLimits {
  // Above its plane by more than this a ground return is not floor noise [m] (the ground
  // continuation's noise) ...
  float raised = 0.02F;
  // ... and it continues a face when it lies within this [m] (facesOfTallObstacles()' reach in
  // cell_classes.cpp) of the face's last return that is not ground, and lower.
  float reach = 0.1F;
};

// Takes out of `ground_of` (per point, its ground plane or -1) the ground returns that continue
// a face: walking each scan line both ways, the ground returns raised above their plane that
// follow a return that is not ground, lower than it and within `reach` of it, with no other
// return between but such ones. `plane_heights`: per plane its
// map height (h0, hx, hy), NaN for planes that are not ground. Returns how many were taken out.
std::size_t dropFaceReturns(std::vector<std::int32_t>& ground_of, const Scan& scan,
                            const std::vector<Eigen::Vector3f>& mapped,
                            const std::vector<Eigen::Vector3d>& plane_heights,
                            const FaceReturnLimits& limits = {});

}  // namespace clearway::detail
