#pragma once

// SCAN.truth.json beside a simulated SCAN.pcd (docs/FORMATS.md): the scene, the sensor, the
// scanner pose, per-point class and surface id, the surfaces seen, and which places each robot
// preset can reach.

#include <filesystem>

#include "clearway/sim/rosi_simulator.h"

namespace clearway::sim {

// SCAN.pcd -> SCAN.truth.json
std::filesystem::path truthPathFor(const std::filesystem::path& scan_file);

void saveGroundTruth(const GroundTruth& truth, const std::filesystem::path& file,
                     const std::string& scan_file_name);
// Throws SceneError naming the problem.
GroundTruth loadGroundTruth(const std::filesystem::path& file);

// Named robots the analytic answers are given for: the LMF's smallest configuration (0.85 m wide),
// the LMF with an arm out (1.0 m wide) and raised (2.1 m high).
std::vector<std::pair<std::string, RobotBox>> robotPresets();

}  // namespace clearway::sim
