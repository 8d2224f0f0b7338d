#pragma once

// Simulated scans and pipeline runs shared by the engine tests.

#include <Eigen/Core>
#include <string>

#include "clearway/pipeline.h"
#include "clearway/sim/builtin_scenes.h"
#include "clearway/sim/rosi_simulator.h"
#include "clearway/traversability/traversability_map.h"

namespace clearway::test {

struct SimulatedRun {
  sim::SimulatedScan simulated;
  PipelineResult result;
};

// Simulates a built-in scene (axis tilted about world x by `tilt_deg`, rolled by `roll_deg`) and
// runs the pipeline with `params`.
SimulatedRun simulateAndSegment(const std::string& scene, int lines,
                                const SegmentationParams& params = {}, double tilt_deg = 0.0,
                                double roll_deg = 0.0,
                                const sim::SceneParameters& scene_parameters = {});

// The map label under a world position of a simulated run (kUnknown outside the map).
CellLabel labelAtWorld(const SimulatedRun& run, const Eigen::Vector3d& world);

// True when the two world positions are joined by traversable (green or orange) cells.
bool connectedInMap(const SimulatedRun& run, const Eigen::Vector3d& from,
                    const Eigen::Vector3d& to);

}  // namespace clearway::test
