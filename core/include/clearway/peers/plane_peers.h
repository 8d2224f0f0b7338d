#pragma once

// General-purpose plane segmentations from PCL, run on a Clearway scan so `clearway-cli bench
// --peers` can time and score them beside our pipeline on the same cloud. Each run includes the
// normals and search structures the method needs, and uses the thread count it is given where the
// method can use threads at all. Parameters are in docs/PERFORMANCE.md.

#include <cstddef>
#include <string>
#include <vector>

#include "clearway/eval/segmentation_accuracy.h"
#include "clearway/scan.h"

namespace clearway::peers {

// The peers' settings in one place, chosen for a RoSi scan (PCL's defaults assume RGB-D images
// and organised camera clouds). docs/PERFORMANCE.md lists them beside the figures.
struct PlanePeerSettings {
  std::size_t min_plane_points = 200;  // as eval's smallest truth plane
  double angle_threshold_deg = 3.0;    // normals this close are one surface
  double distance_threshold = 0.03;    // [m] three times the LMS200's range noise
  // Integral-image normals: our z is the turntable axis, not a camera's depth, and PCL's
  // depth-change test compares the z of neighbours, so it is loose (10 cm at z = 0).
  float depth_change_factor = 0.05F;
  float normal_smoothing_size = 10.0F;  // [pixels]
  int neighbours = 20;                  // kNN normals and region growing
  float max_curvature = 0.05F;          // region growing: flatter than this seeds and grows
  int ransac_iterations = 200;
  int max_planes = 40;  // iterative RANSAC stops after this many
};

struct PlanePeer {
  std::string name;
  // Why the method cannot run on `scan` (e.g. it needs an organised scan); empty when it can.
  std::string (*unsuitable)(const Scan& scan);
  eval::PointPlanes (*run)(const Scan& scan, int threads, const PlanePeerSettings& settings);
};

// All plane peers, in the order the benchmark prints them.
const std::vector<PlanePeer>& planePeers();

// PCL OrganizedMultiPlaneSegmentation with its refinement step (segmentAndRefine) on
// integral-image normals (single-threaded in PCL).
eval::PointPlanes pclOrganizedMultiPlane(const Scan& scan, int threads,
                                         const PlanePeerSettings& settings = {});
// PCL RegionGrowing on kNN normals (NormalEstimationOMP, k-d tree), a least-squares plane per
// region.
eval::PointPlanes pclRegionGrowing(const Scan& scan, int threads,
                                   const PlanePeerSettings& settings = {});
// PCL SACSegmentation RANSAC run again and again on the points no plane has taken yet.
eval::PointPlanes pclRansacPlanes(const Scan& scan, int threads,
                                  const PlanePeerSettings& settings = {});

}  // namespace clearway::peers
