#include <iostream>
#include <nlohmann/json.hpp>

#include "arguments.h"
#include "clearway/io/result_writer.h"
#include "clearway/io/scan_io.h"
#include "clearway/pipeline.h"
#include "commands.h"
#include "robot_options.h"

namespace clearway::cli {

int runSegment(const std::vector<std::string>& words) {
  const Arguments arguments(
      words, {"quiet"}, withRobotOptions({"o", "output", "params", "threads", "method", "rings"}));
  arguments.expectPositional(1, "one scan: clearway-cli segment SCAN -o DIR [options]");
  const auto output = arguments.option("o") ? arguments.option("o") : arguments.option("output");
  if (!output) throw UsageError("-o DIR is required");
  SegmentationParams params = paramsFromArguments(arguments);
  const int threads = int(arguments.integer("threads", 2, 1, 64));

  const std::filesystem::path scan_file = arguments.positional()[0];
  LoadOptions load;
  load.rings = std::size_t(arguments.integer("rings", 0, 0, kMaxRings));
  const Scan scan = loadScan(scan_file, load);
  const PipelineResult result = runPipeline(scan, params, threads);
  writeResultFolder(result, params, scan_file.filename().string(), *output);
  if (!arguments.flag("quiet")) {
    std::cout << "ground found: " << (result.trusted() ? "yes" : "NO") << "\n";
    if (!result.trusted()) std::cout << "reason: " << result.analysis.reason << "\n";
    std::cout << "planes: " << result.analysis.planes.planes.size() << " ("
              << result.analysis.candidate_planes
              << " candidates), segments: " << result.analysis.segments.size() << "\n";
    std::cout << "cells: traversable " << result.map.counts[1] << ", careful "
              << result.map.counts[2] << ", obstacle " << result.map.counts[3] << ", impassable "
              << result.map.counts[4] << "\n";
    std::cout << "timing [ms]:";
    for (const StageTiming& stage : result.timings)
      std::cout << " " << stage.stage << " " << stage.milliseconds;
    std::cout << ", total " << result.total_ms << "\n";
    std::cout << "written to " << output->c_str() << "\n";
  }
  return 0;
}

}  // namespace clearway::cli
