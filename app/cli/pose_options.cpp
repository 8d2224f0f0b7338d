#include "pose_options.h"

#include <stdexcept>

#include "clearway/hardware/acquisition_files.h"
#include "clearway/io/scan_io.h"
#include "commands.h"

namespace clearway::cli {

std::set<std::string> withPoseOptions(std::set<std::string> options) {
  options.insert({"pose", "up", "self-hit-radius", "rings"});
  return options;
}

LoadedScan loadScanWithPose(const std::filesystem::path& file, const Arguments& arguments,
                            SegmentationParams& params) {
  params.scan.self_hit_radius =
      arguments.number("self-hit-radius", params.scan.self_hit_radius, 0.0, 5.0);
  PoseRequest request;
  try {
    if (const auto pose = arguments.option("pose")) request.pose = parsePoseText(*pose);
    if (const auto up = arguments.option("up")) {
      if (*up == "none") {
        params.ground.estimate_up = 0;
      } else if (*up == "auto") {
        params.ground.estimate_up = 1;
      } else {
        request.up = parseUpText(*up);
      }
    }
  } catch (const std::invalid_argument& error) {
    throw UsageError(error.what());
  }
  LoadOptions options;
  options.self_hit_radius = params.scan.self_hit_radius;
  options.rings = std::size_t(arguments.integer("rings", 0, 0, kMaxRings));
  LoadedScan loaded{loadScan(file, options), {}};
  loaded.pose = resolveScanPose(loaded.scan, request);
  return loaded;
}

std::string describePose(const PoseResolution& pose) {
  std::string text = "pose: " + std::string(poseSourceName(pose.source));
  if (!pose.detail.empty()) text += " (" + pose.detail + ")";
  return text;
}

std::string partialScanCaution(const std::filesystem::path& scan) {
  const hardware::ScanCompleteness completeness = hardware::scanCompleteness(scan);
  if (!completeness.partial) return {};
  const std::string why = completeness.reason.empty()
                              ? "the acquisition ended before the turn was complete"
                              : "the acquisition ended early (" + completeness.reason + ")";
  return "partial scan: " + why +
         ": what the rest of the turn would have seen is unknown, not free";
}

}  // namespace clearway::cli
