#pragma once

// General-purpose plane segmentations from PCL, run on a Clearway scan so `clearway-cli bench
// --peers` can time and score them beside our pipeline on the same cloud. Each run includes the
// normals and search structures the method needs, and uses the thread count it is given where the
// method can use threads at all. Parameters are in docs/PERFORMANCE.md.

#include <string>
#include <vector>

#include "clearway/eval/segmentation_accuracy.h"
#include "clearway/scan.h"

namespace clearway::peers {

struct PlanePeer {
  std::string name;
  // Why the method cannot run on `scan` (e.g. it needs an organised scan); empty when it can.
  std::string (*unsuitable)(const Scan& scan);
  eval::PointPlanes (*run)(const Scan& scan, int threads);
};

// All plane peers, in the order the benchmark prints them.
const std::vector<PlanePeer>& planePeers();

// PCL OrganizedMultiPlaneSegmentation on integral-image normals (single-threaded in PCL).
eval::PointPlanes pclOrganizedMultiPlane(const Scan& scan, int threads);
// PCL RegionGrowing on kNN normals (NormalEstimationOMP, k-d tree), a least-squares plane per
// region.
eval::PointPlanes pclRegionGrowing(const Scan& scan, int threads);
// PCL SACSegmentation RANSAC run again and again on the points no plane has taken yet.
eval::PointPlanes pclRansacPlanes(const Scan& scan, int threads);

}  // namespace clearway::peers
