#pragma once

// The `clearway-cli segment` output folder (docs/FORMATS.md): report.json, labels.pgm, map.pgm +
// map.yaml (ROS map_server), traversability.png, scene.ply, point_classes.u8. Every file is
// written atomically.

#include <filesystem>
#include <string>

#include "clearway/pipeline.h"

namespace clearway {

void writeResultFolder(const PipelineResult& result, const SegmentationParams& params,
                       const std::string& scan_name, const std::filesystem::path& folder);

// The parts, for the GUI's export menu.
std::string reportJson(const PipelineResult& result, const SegmentationParams& params,
                       const std::string& scan_name);
void writeLabelsPgm(const TraversabilityMap& map, const std::filesystem::path& file);
void writeReasonsPgm(const TraversabilityMap& map, const std::filesystem::path& file);
// 1 where the robot can get from its own pose, 0 elsewhere.
void writeReachPgm(const TraversabilityMap& map, const std::filesystem::path& file);
void writeRosMap(const TraversabilityMap& map,
                 const std::filesystem::path& pgm_file);  // + .yaml beside
// The map in the console's colours. With `withhold_drivable` (an up direction only estimated,
// as the console withholds it until the operator confirms it) no cell is drawn as one the robot
// may drive: those are drawn as not seen.
void writeTraversabilityPng(const TraversabilityMap& map, const std::filesystem::path& file,
                            bool withhold_drivable = false);
void writeScenePly(const SceneGeometry& scene, const std::filesystem::path& file);

}  // namespace clearway
