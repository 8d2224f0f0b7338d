#pragma once

// Where two ground planes meet on the map grid: the step kept at their border, and the smallest
// step between each pair of planes that touch (docs/ALGORITHM.md, "Where two ground levels meet").

#include <Eigen/Core>
#include <vector>

#include "clearway/segmentation/scan_analysis.h"

namespace clearway::detail {

// Raises MapInputs::seam_step of both cells wherever cells of two ground planes meet more than
// EdgeLimit::kTouchingStep apart, side by side or across one unobserved cell (which the robot's
// box may stand over): at least the planes' difference there (`plane_heights`, per plane, as
// EdgeLimit::plane_heights), plus what either side is measured to.
void markPlaneEdges(MapInputs& inputs, const std::vector<Eigen::Vector3d>& plane_heights,
                    const std::vector<Plane>& planes);

// Where cells of two ground planes touch, and the smallest step between them.
std::vector<GroundContact> groundContacts(const MapInputs& inputs);

}  // namespace clearway::detail
