#pragma once

// The whole method, scan in, result out: stages 1-4 once per scan (ScanAnalysis), stages 5-6 per
// robot size (reuseAnalysis keeps the former when only the robot changes).

#include <optional>
#include <string>
#include <vector>

#include "clearway/point_class.h"
#include "clearway/progress.h"
#include "clearway/scan.h"
#include "clearway/scene/scene_geometry.h"
#include "clearway/segmentation/params.h"
#include "clearway/segmentation/scan_analysis.h"
#include "clearway/traversability/traversability_map.h"

namespace clearway {

struct PipelineResult {
  ScanAnalysis analysis;
  TraversabilityMap map;
  SceneGeometry scene;
  RobotParams robot;
  std::vector<PointClass> point_classes;  // per scan point
  std::optional<GoalResult> goal;         // "Can it get there?", when a goal was asked
  std::vector<StageTiming> timings;       // analysis stages, then traversability and scene
  double total_ms = 0.0;

  bool trusted() const { return analysis.ground_found; }
};

// Throws std::invalid_argument for invalid parameters, OperationCancelled on cancel.
PipelineResult runPipeline(const Scan& scan, const SegmentationParams& params, int threads = 2,
                           const ProgressCallback& progress = {});

// Stages 5-6 only, for a new robot, on an existing analysis of the same scan.
PipelineResult rerunForRobot(const Scan& scan, ScanAnalysis analysis,
                             const SegmentationParams& params, int threads = 2,
                             const ProgressCallback& progress = {});

// Per-point classes from the planes and the map.
std::vector<PointClass> classifyPoints(const Scan& scan, const ScanAnalysis& analysis,
                                       const RobotParams& robot);

}  // namespace clearway
