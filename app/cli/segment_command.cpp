#include <Eigen/Core>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "arguments.h"
#include "clearway/io/result_writer.h"
#include "clearway/io/scan_io.h"
#include "clearway/pipeline.h"
#include "commands.h"
#include "pose_options.h"
#include "robot_options.h"

namespace clearway::cli {

int runSegment(const std::vector<std::string>& words) {
  const Arguments arguments(
      words, {"quiet"},
      withPoseOptions(withRobotOptions({"o", "output", "params", "threads", "method", "goal"})));
  arguments.expectPositional(1, "one scan: clearway-cli segment SCAN -o DIR [options]");
  const auto output = arguments.option("o") ? arguments.option("o") : arguments.option("output");
  if (!output) throw UsageError("-o DIR is required");
  SegmentationParams params = paramsFromArguments(arguments);
  const int threads = int(arguments.integer("threads", kDefaultThreads, 1, kMaxThreads));

  std::optional<Eigen::Vector2d> goal;
  if (const auto text = arguments.option("goal")) {
    double x = 0.0, y = 0.0;
    char comma = 0;
    std::istringstream stream(*text);
    if (!(stream >> x >> comma >> y) || comma != ',' || !stream.eof() || !std::isfinite(x) ||
        !std::isfinite(y))
      throw UsageError("--goal X,Y (map frame, metres): got '" + *text + "'");
    goal = Eigen::Vector2d(x, y);
  }

  const std::filesystem::path scan_file = arguments.positional()[0];
  const LoadedScan loaded = loadScanWithPose(scan_file, arguments, params);
  PipelineResult result = runPipeline(loaded.scan, params, threads);
  if (goal) result.goal = planPath(result.map, goal->x(), goal->y());
  writeResultFolder(result, params, scan_file.filename().string(), *output);
  if (!arguments.flag("quiet")) {
    std::cout << describePose(loaded.pose) << "\n";
    std::cout << "ground found: " << (result.trusted() ? "yes" : "NO") << "\n";
    if (const std::string partial = partialScanCaution(scan_file); !partial.empty())
      std::cout << "caution: " << partial << "\n";
    // The console draws nothing traversable until the operator confirms an estimated up
    // direction; a batch run writes the map, and says on every answer that it rests on it.
    const bool estimated =
        result.analysis->pose_source == PoseSource::kEstimated && result.trusted();
    if (estimated)
      std::cout << "up direction: estimated from the scan (confidence "
                << result.analysis->up_confidence
                << "): the map holds only if it is right; give --up or --pose to be sure "
                   "(traversability.png draws nothing traversable until then)\n";
    // With ground found, a reason says why nothing is green (too sparse, or fits nowhere).
    if (!result.reason.empty()) std::cout << "reason: " << result.reason << "\n";
    std::cout << "planes: " << result.analysis->planes.planes.size() << " ("
              << result.analysis->candidate_planes
              << " candidates), segments: " << result.analysis->segments.size() << "\n";
    std::cout << "cells: traversable " << result.map.counts[1] << ", careful "
              << result.map.counts[2] << ", obstacle " << result.map.counts[3] << ", impassable "
              << result.map.counts[4] << "\n";
    std::cout << "reachable cells: " << result.map.reachable_cells << ", fit but unreachable "
              << result.map.fits_not_reachable_cells << "\n";
    if (!result.map.reach_limit.empty()) std::cout << "reach: " << result.map.reach_limit << "\n";
    if (result.goal)
      std::cout << "goal: " << (result.goal->reachable ? "reachable" : "NOT reachable")
                << (estimated ? " (if the estimated up direction is right)" : "")
                << (result.goal->reachable
                        ? ", path " + std::to_string(result.goal->length_m) + " m" +
                              (result.goal->unvouched_m > 0.0
                                   ? ", " + std::to_string(result.goal->unvouched_m) +
                                         " m of it over ground not vouched for (too sparse, or "
                                         "not seen up to the robot's height): drive it with care"
                                   : "")
                        : ": " + result.goal->reason)
                << "\n";
    std::cout << "timing [ms]:";
    for (const StageTiming& stage : result.timings)
      std::cout << " " << stage.stage << " " << stage.milliseconds;
    std::cout << ", total " << result.total_ms << "\n";
    std::cout << "written to " << output->c_str() << "\n";
  }
  return 0;
}

}  // namespace clearway::cli
