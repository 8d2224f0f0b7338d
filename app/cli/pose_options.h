#pragma once

// Command-line options that say how to read a scan (--self-hit-radius, --rings) and where the
// scanner was (--pose, --up), and the one way every command loads a scan with them: core's
// loadScan and resolveScanPose (pose.h).

#include <filesystem>
#include <set>
#include <string>

#include "arguments.h"
#include "clearway/pose.h"
#include "clearway/segmentation/params.h"

namespace clearway::cli {

std::set<std::string> withPoseOptions(std::set<std::string> options);

struct LoadedScan {
  Scan scan;
  PoseResolution pose;
};

// Loads `file` with params.scan.self_hit_radius (or --self-hit-radius), then applies --pose /
// --up X,Y,Z, the sidecar and the file's own pose in that order. `--up none` turns the estimate
// off in `params`, `--up auto` (the default) leaves it on. Throws UsageError for malformed values.
LoadedScan loadScanWithPose(const std::filesystem::path& file, const Arguments& arguments,
                            SegmentationParams& params);

// One line for people: "pose: sidecar (garage.pose.json)".
std::string describePose(const PoseResolution& pose);

// What a partial acquisition's scan must say of itself ("partial scan: the acquisition ended early
// (REASON): what the rest of the turn would have seen is unknown, not free"), else empty: its
// SCAN.acquisition.json, or its name (hardware::scanCompleteness).
std::string partialScanCaution(const std::filesystem::path& scan);

}  // namespace clearway::cli
