#pragma once

// Accuracy of any plane segmentation, ours or a peer's, against the simulator's truth: which
// truth planes were found (recall, precision, normal error, as evaluate() scores them) and how
// clean the points assigned to each plane are, so a fast but wrong segmentation cannot win a
// benchmark.

#include <cstdint>
#include <vector>

#include "clearway/eval/evaluation.h"

namespace clearway::eval {

// Planes with, per scan point, the index of the plane it was assigned to or -1.
struct PointPlanes {
  std::vector<ResultPlane> planes;
  std::vector<std::int32_t> point_plane;
};

struct SegmentationAccuracy {
  PlaneScore planes;
  std::size_t assigned_points = 0;  // points with a plane (that have a truth surface)
  // Of those, the share whose true surface is planar and lies on the assigned plane (within the
  // options' normal and offset tolerances): points on a coplanar neighbour count as pure.
  double point_purity = 0.0;
  // Points on planar truth surfaces that got a plane, over all points on planar truth surfaces.
  double coverage = 0.0;
};

// Our validated planes and point assignment from an analysis (ScanAnalysis::planes).
PointPlanes pointPlanesOf(const ScanAnalysis& analysis);

// Throws std::invalid_argument when point_plane does not have one entry per truth point.
SegmentationAccuracy scoreSegmentation(const sim::GroundTruth& truth, const PointPlanes& result,
                                       const EvaluationOptions& options = {});

}  // namespace clearway::eval
