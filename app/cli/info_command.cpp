#include <iostream>

#include "arguments.h"
#include "clearway/io/scan_io.h"
#include "clearway/scan_summary.h"
#include "commands.h"
#include "pose_options.h"

namespace clearway::cli {

int runInfo(const std::vector<std::string>& words) {
  const Arguments arguments(words, {"json"}, withPoseOptions({}));
  arguments.expectPositional(1, "one scan file: clearway-cli info [--json] FILE");
  SegmentationParams params;
  const LoadedScan loaded = loadScanWithPose(arguments.positional()[0], arguments, params);
  ScanSummary summary = summarise(loaded.scan);
  summary.pose_source = std::string(poseSourceName(loaded.pose.source));
  summary.pose_detail = loaded.pose.detail;
  if (const std::string partial = partialScanCaution(arguments.positional()[0]); !partial.empty())
    summary.caution = summary.caution.empty() ? partial : summary.caution + "; " + partial;
  std::cout << (arguments.flag("json") ? toJson(summary) + "\n" : toText(summary));
  return 0;
}

}  // namespace clearway::cli
