#pragma once

// The whole method, scan in, result out: stages 1-4 once per scan (ScanAnalysis), stages 5-6 per
// robot size (rerunForRobot shares the former when only the robot changes).

#include <memory>
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

// Threads the engine uses unless told otherwise (clearway-cli --threads, clearway --threads): the
// operator console's computer has two cores, and so has the CI machine.
inline constexpr int kDefaultThreads = 2;
// The most threads a caller may ask for (the command line's and the console's range).
inline constexpr int kMaxThreads = 64;

struct PipelineResult {
  // Stages 1-4, read-only and shared by every result of the same scan: a re-run for another robot
  // hands the same analysis on instead of copying it (tens of MB at 1M points). Never null.
  std::shared_ptr<const ScanAnalysis> analysis;
  TraversabilityMap map;
  SceneGeometry scene;
  RobotParams robot;
  std::vector<PointClass> point_classes;  // per scan point
  std::optional<GoalResult> goal;         // "Can it get there?", when a goal was asked
  std::vector<StageTiming> timings;       // analysis stages, then traversability and scene
  double total_ms = 0.0;
  // Why the result cannot be trusted or shows nothing traversable, empty when all is well: the
  // analysis' own reason, or for this robot that the scan is too sparse to vouch for any cell.
  std::string reason;

  bool trusted() const { return analysis && analysis->ground_found; }
};

// Throws std::invalid_argument for invalid parameters, OperationCancelled on cancel.
PipelineResult runPipeline(const Scan& scan, const SegmentationParams& params,
                           int threads = kDefaultThreads, const ProgressCallback& progress = {});

// Stages 5-6 only, for a new robot, on an existing analysis of the same scan.
PipelineResult rerunForRobot(const Scan& scan, std::shared_ptr<const ScanAnalysis> analysis,
                             const SegmentationParams& params, int threads = kDefaultThreads,
                             const ProgressCallback& progress = {});

// Per-point classes from the planes and the map.
std::vector<PointClass> classifyPoints(const Scan& scan, const ScanAnalysis& analysis,
                                       const RobotParams& robot);

}  // namespace clearway
