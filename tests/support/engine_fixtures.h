#pragma once

// Simulated scans and pipeline runs shared by the engine tests.

#include <Eigen/Core>
#include <string>

#include "clearway/eval/evaluation.h"
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

// Simulates `scene` from a RoSi 1 m above the origin, its turntable axis along world x, 200 lines
// out to 8 m (the hand-built scenes' scanner), and runs the pipeline with `params`.
SimulatedRun simulateFromOrigin(const sim::Scene& scene, const SegmentationParams& params = {});

// An unturned box of `point_class` for a scene built in a test: centre and full edge lengths.
sim::Primitive solidBox(const std::string& name, PointClass point_class,
                        const Eigen::Vector3d& center, const Eigen::Vector3d& size);

// Simulates `scene` from the robot's arm as the probe scenes have it (1.2 m above the origin, the
// turntable axis ahead tilted down, (1, 0, -0.3)) with `sensor`, saved and loaded as
// simulateSavedAndSegment does, and runs the pipeline with `params`.
SimulatedRun simulateFromTheArm(const sim::Scene& scene, const sim::SensorModel& sensor,
                                const SegmentationParams& params = {});

// Simulates `scene` and runs the pipeline on the scan as the console would have it: saved as a
// PCD (single-precision coordinates) and loaded again, as `clearway-cli simulate` then `segment`.
SimulatedRun simulateSavedAndSegment(const sim::Scene& scene, const sim::SensorModel& sensor,
                                     const sim::ScannerPlacement& placement,
                                     const SegmentationParams& params = {});

// Simulates `scene` as a nodding scanner's file holds it (3DTK's walkway, octomap's stairs): the
// points turned into a level frame at the scanner (z up), no turntable angle per line, the pose
// the identity; the fans turn about `placement.axis`. The truth's placement is levelled the same
// way, so that evaluateRun() and labelAtWorld() read the map in the world. Runs the pipeline.
SimulatedRun simulateNodding(const sim::Scene& scene, const sim::SensorModel& sensor,
                             const sim::ScannerPlacement& placement,
                             const SegmentationParams& params = {});

// The run's map scored against the simulator's truth (`clearway-cli eval`'s measures) for the
// robot of `params`.
eval::Evaluation evaluateRun(const SimulatedRun& run, const SegmentationParams& params = {});

// The map label under a world position of a simulated run (kUnknown outside the map).
CellLabel labelAtWorld(const SimulatedRun& run, const Eigen::Vector3d& world);
// Its reason (kNone outside the map).
CellReason reasonAtWorld(const SimulatedRun& run, const Eigen::Vector3d& world);

// The scan with its lines in reverse order, each line's returns as they were (a multi-beam frame
// stored bottom up instead of top down); intensities follow their points.
Scan linesReversed(const Scan& scan);

// True when the two world positions are joined by traversable (green or orange) cells.
bool connectedInMap(const SimulatedRun& run, const Eigen::Vector3d& from,
                    const Eigen::Vector3d& to);

}  // namespace clearway::test
