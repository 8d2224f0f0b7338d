#include "engine_fixtures.h"

#include "clearway/io/scan_io.h"

#include <unistd.h>
#include <Eigen/Geometry>
#include <filesystem>
#include <limits>
#include <numbers>
#include <queue>

namespace clearway::test {
namespace {

Eigen::Vector2i cellOfWorld(const SimulatedRun& run, const Eigen::Vector3d& world) {
  const Eigen::Isometry3d map_from_world =
      run.result.analysis->map_from_scanner *
      run.simulated.truth.placement.worldFromScanner().inverse();
  const Eigen::Vector3d m = map_from_world * world;
  return run.result.map.grid.cellOf(m.x(), m.y());
}

bool traversable(CellLabel label) {
  return label == CellLabel::kTraversable || label == CellLabel::kCareful;
}

}  // namespace

SimulatedRun simulateAndSegment(const std::string& scene_name, int lines,
                                const SegmentationParams& params, double tilt_deg, double roll_deg,
                                const sim::SceneParameters& scene_parameters) {
  const sim::Scene scene = *sim::builtinScene(scene_name, scene_parameters);
  sim::SensorModel sensor;
  sensor.lines = lines;
  sim::ScannerPlacement placement = sim::defaultPlacement(scene);
  placement.axis = Eigen::AngleAxisd(tilt_deg * std::numbers::pi / 180, Eigen::Vector3d::UnitX()) *
                   placement.axis;
  placement.axis_roll_deg = roll_deg;
  SimulatedRun run;
  run.simulated = sim::simulateRosi(scene, sensor, placement);
  run.result = runPipeline(run.simulated.scan, params);
  return run;
}

SimulatedRun simulateFromOrigin(const sim::Scene& scene, const SegmentationParams& params) {
  sim::SensorModel sensor;
  sensor.lines = 200;
  sensor.max_range = 8.0;
  sim::ScannerPlacement placement;
  placement.position = {0.0, 0.0, 1.0};
  placement.axis = {1.0, 0.0, 0.0};
  SimulatedRun run;
  run.simulated = sim::simulateRosi(scene, sensor, placement);
  run.result = runPipeline(run.simulated.scan, params);
  return run;
}

sim::Primitive solidBox(const std::string& name, PointClass point_class,
                        const Eigen::Vector3d& center, const Eigen::Vector3d& size) {
  sim::Primitive primitive;
  primitive.name = name;
  primitive.point_class = point_class;
  primitive.center = center;
  primitive.size = size;
  return primitive;
}

SimulatedRun simulateFromTheArm(const sim::Scene& scene, const sim::SensorModel& sensor,
                                const SegmentationParams& params) {
  sim::ScannerPlacement placement;
  placement.position = {0.0, 0.0, 1.2};
  placement.axis = Eigen::Vector3d(1.0, 0.0, -0.3).normalized();
  return simulateSavedAndSegment(scene, sensor, placement, params);
}

SimulatedRun simulateSavedAndSegment(const sim::Scene& scene, const sim::SensorModel& sensor,
                                     const sim::ScannerPlacement& placement,
                                     const SegmentationParams& params) {
  SimulatedRun run;
  run.simulated = sim::simulateRosi(scene, sensor, placement);
  const std::filesystem::path file = std::filesystem::temp_directory_path() /
                                     ("clearway_fixture_" + std::to_string(::getpid()) + ".pcd");
  saveRosiPcd(run.simulated.scan, file);
  run.simulated.scan = loadScan(file);
  std::filesystem::remove(file);
  run.result = runPipeline(run.simulated.scan, params);
  return run;
}

SimulatedRun simulateNodding(const sim::Scene& scene, const sim::SensorModel& sensor,
                             const sim::ScannerPlacement& placement,
                             const SegmentationParams& params) {
  SimulatedRun run;
  run.simulated = sim::simulateRosi(scene, sensor, placement);
  Scan& scan = run.simulated.scan;
  const Eigen::Matrix3d level = placement.worldFromScanner().linear();
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!scan.isValid(i)) continue;
    const Point3f& p = scan.points[i];
    const Eigen::Vector3d q = level * Eigen::Vector3d(p.x, p.y, p.z);
    scan.points[i] = {float(q.x()), float(q.y()), float(q.z())};
  }
  for (ScanLine& line : scan.lines)
    line.beta = std::numeric_limits<double>::quiet_NaN();
  scan.sensor_pose = SensorPose{};
  // A placement whose axis is z and roll 0 is the identity turn: the level frame at the scanner.
  run.simulated.truth.placement.axis = Eigen::Vector3d::UnitZ();
  run.simulated.truth.placement.axis_roll_deg = 0.0;
  run.result = runPipeline(scan, params);
  return run;
}

eval::Evaluation evaluateRun(const SimulatedRun& run, const SegmentationParams& params) {
  eval::SegmentationResult result;
  result.robot = {params.robot.width, params.robot.length, params.robot.height,
                  params.robot.max_step};
  result.map = eval::resultMapOf(run.result.map.grid, run.result.map.labels,
                                 run.result.analysis->map_from_scanner);
  result.has_map = true;
  return eval::evaluate(run.simulated.truth, result);
}

CellLabel labelAtWorld(const SimulatedRun& run, const Eigen::Vector3d& world) {
  const Eigen::Vector2i cell = cellOfWorld(run, world);
  if (!run.result.map.grid.inside(cell.x(), cell.y())) return CellLabel::kUnknown;
  return run.result.map.label(cell.x(), cell.y());
}

CellReason reasonAtWorld(const SimulatedRun& run, const Eigen::Vector3d& world) {
  const Eigen::Vector2i cell = cellOfWorld(run, world);
  const MapGrid& grid = run.result.map.grid;
  if (!grid.inside(cell.x(), cell.y())) return CellReason::kNone;
  return CellReason(run.result.map.reasons[grid.index(cell.x(), cell.y())]);
}

bool connectedInMap(const SimulatedRun& run, const Eigen::Vector3d& from,
                    const Eigen::Vector3d& to) {
  const TraversabilityMap& map = run.result.map;
  const Eigen::Vector2i start = cellOfWorld(run, from), goal = cellOfWorld(run, to);
  if (!map.grid.inside(start.x(), start.y()) || !traversable(map.label(start.x(), start.y())))
    return false;
  std::vector<bool> seen(map.grid.cells(), false);
  std::queue<Eigen::Vector2i> frontier;
  frontier.push(start);
  seen[map.grid.index(start.x(), start.y())] = true;
  while (!frontier.empty()) {
    const Eigen::Vector2i cell = frontier.front();
    frontier.pop();
    if ((cell - goal).cwiseAbs().maxCoeff() <= 4) return true;  // within 0.2 m of the goal
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc) {
        const Eigen::Vector2i next = cell + Eigen::Vector2i(dc, dr);
        if (!map.grid.inside(next.x(), next.y())) continue;
        const std::size_t index = map.grid.index(next.x(), next.y());
        if (seen[index] || !traversable(map.label(next.x(), next.y()))) continue;
        seen[index] = true;
        frontier.push(next);
      }
  }
  return false;
}

Scan linesReversed(const Scan& scan) {
  Scan reversed = scan;
  reversed.points.clear();
  reversed.status.clear();
  reversed.intensity.clear();
  reversed.lines.clear();
  for (std::size_t l = scan.lines.size(); l-- > 0;) {
    const ScanLine& stored = scan.lines[l];
    ScanLine line = stored;
    line.first = reversed.points.size();
    for (std::size_t i = stored.first; i < stored.first + stored.count; ++i) {
      reversed.points.push_back(scan.points[i]);
      reversed.status.push_back(scan.status[i]);
      if (!scan.intensity.empty()) reversed.intensity.push_back(scan.intensity[i]);
    }
    reversed.lines.push_back(line);
  }
  return reversed;
}

}  // namespace clearway::test
