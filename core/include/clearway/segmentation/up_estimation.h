#pragma once

// The up direction of a scan that came without a pose, estimated from its validated planes
// (docs/ALGORITHM.md, "Up direction without a pose"). The estimate is invariant to how the scan is
// turned: it never reads the file's own axes, only the geometry. When the evidence does not single
// out one floor, it refuses rather than guess: a wall taken for the floor is one scene away from a
// green wall.

#include <Eigen/Core>
#include <string>

#include "clearway/scan.h"
#include "clearway/segmentation/params.h"
#include "clearway/segmentation/planes.h"

namespace clearway {

struct UpEstimate {
  bool found = false;
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  // world up in the scanner frame, when found
  // 0..1: how clearly the chosen floor beats the next plausible one (1 - runner-up / best score).
  double confidence = 0.0;
  int hypotheses = 0;  // distinct plausible up directions
  std::string reason;  // why nothing was chosen
};

UpEstimate estimateUp(const Scan& scan, const ValidatedPlanes& planes, const GroundParams& params);

}  // namespace clearway
