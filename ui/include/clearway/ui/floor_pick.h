#pragma once

// "This is the floor": the operator points at the floor in the 3D view and the plane through that
// point gives the scan's up direction (issue #11, item 2). Plain geometry on the scan, no Qt, so
// tests can hand it a point without a renderer.

#include <Eigen/Core>
#include <optional>
#include <string>

#include "clearway/scan.h"
#include "clearway/segmentation/scan_analysis.h"

namespace clearway::ui {

struct FloorPick {
  std::optional<Eigen::Vector3d> up;  // world up seen from the scanner; empty when refused
  std::string how;                    // "plane 3 (1234 points)" or "fitted to 87 nearby points"
  std::string reason;                 // why not, when refused
};

// The nearest valid scan point to `scanner_point` (scanner frame) must lie within
// kFloorPickReach; its validated plane gives the normal, else a least-squares plane fitted to the
// points around it (refused when they are too few or not flat). The normal is turned towards the
// scanner: the scanner looks at the floor from above.
FloorPick floorUpAt(const Scan& scan, const ScanAnalysis& analysis,
                    const Eigen::Vector3d& scanner_point);

// A pick farther than this from every measured point hit nothing the scan saw [m].
inline constexpr double kFloorPickReach = 0.3;
// The neighbourhood fitted when the picked point belongs to no validated plane [m].
inline constexpr double kFloorFitRadius = 0.25;
// Fewer points than this around the pick do not define a plane.
inline constexpr int kFloorFitMinPoints = 20;
// The neighbourhood is flat when its smallest spread is below this share of the next one
// (eigenvalue ratio of the covariance).
inline constexpr double kFloorFlatness = 0.05;

}  // namespace clearway::ui
