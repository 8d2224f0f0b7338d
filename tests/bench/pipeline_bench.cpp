// Google Benchmark micro-benchmarks of the pipeline on simulated RoSi scans (docs/PERFORMANCE.md).
// Speed is measured here, never asserted in a test. Run: build/tests/bench/clearway_bench

#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <string>
#include <utility>

#include "clearway/memory_tuning.h"
#include "clearway/pipeline.h"
#include "clearway/sim/builtin_scenes.h"
#include "clearway/sim/rosi_simulator.h"

namespace {

using namespace clearway;

// Simulated scans of a built-in scene, made once per scene and line count: garage 80 lines =
// 14,400 points, 423 = 76,140.
const Scan& sceneScan(const std::string& name, int lines) {
  static std::map<std::pair<std::string, int>, Scan> scans;
  auto it = scans.find({name, lines});
  if (it == scans.end()) {
    const sim::Scene scene = *sim::builtinScene(name);
    sim::SensorModel sensor;
    sensor.lines = lines;
    it = scans
             .emplace(std::pair{name, lines},
                      sim::simulateRosi(scene, sensor, sim::defaultPlacement(scene)).scan)
             .first;
  }
  return it->second;
}

const Scan& garageScan(int lines) {
  return sceneScan("garage", lines);
}

void BM_Pipeline(benchmark::State& state) {
  const Scan& scan = garageScan(int(state.range(0)));
  const int threads = int(state.range(1));
  std::map<std::string, double> stage_ms;
  for (auto _ : state) {
    const PipelineResult result = runPipeline(scan, {}, threads);
    for (const StageTiming& stage : result.timings)
      stage_ms[stage.stage] += stage.milliseconds;
  }
  for (const auto& [stage, total] : stage_ms)
    state.counters[stage + "_ms"] = total / double(state.iterations());
  state.counters["points"] = double(scan.size());
  state.counters["points/s"] =
      benchmark::Counter(double(scan.size()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_Pipeline)
    ->Args({80, 2})
    ->Args({423, 1})
    ->Args({423, 2})
    ->Unit(benchmark::kMillisecond);

void BM_LineSegments(benchmark::State& state) {
  const Scan& scan = garageScan(423);
  LineParams params;
  params.method = state.range(0) ? LineMethod::kHough : LineMethod::kSplitAndMerge;
  for (auto _ : state)
    benchmark::DoNotOptimize(detectLineSegments(scan, params, 2));
  state.SetLabel(state.range(0) ? "hough" : "split-and-merge");
}
BENCHMARK(BM_LineSegments)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_AnalyseScan(benchmark::State& state) {
  const Scan& scan = garageScan(423);
  for (auto _ : state)
    benchmark::DoNotOptimize(analyseScan(scan, {}, 2));
}
BENCHMARK(BM_AnalyseScan)->Unit(benchmark::kMillisecond);

// Stair detection alone (docs/ALGORITHM.md, 4b): what it adds to every 76,140-point scan, with
// no stairs (garage) and with 4 and 12 steps (hallway, stairwell). Read the CPU column.
const char* const kStairScenes[] = {"garage", "hallway", "stairwell"};

void BM_DetectStairs(benchmark::State& state) {
  const std::string name = kStairScenes[state.range(0)];
  const Scan& scan = sceneScan(name, 423);
  const ScanAnalysis analysis = analyseScan(scan, {}, 2);
  std::size_t found = 0;
  for (auto _ : state)
    found = detectStairs(scan, analysis.map_from_scanner, {}).size();
  state.SetLabel(name + ", " + std::to_string(found) + " staircase(s)");
}
BENCHMARK(BM_DetectStairs)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

// Classing the points on the flights (part of classifyPoints).
void BM_ClassifyStairPoints(benchmark::State& state) {
  const Scan& scan = sceneScan(kStairScenes[state.range(0)], 423);
  const ScanAnalysis analysis = analyseScan(scan, {}, 2);
  std::vector<PointClass> classes(scan.size(), PointClass::kNone);
  for (auto _ : state) {
    classifyStairPoints(scan, analysis, classes);
    benchmark::DoNotOptimize(classes.data());
  }
  state.SetLabel(kStairScenes[state.range(0)]);
}
BENCHMARK(BM_ClassifyStairPoints)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

// What a robot slider move costs: stages 5-6 on a cached analysis, as the console calls it (the
// hand-over of the kept analysis included), on 76,140 and on 1,000,080 points.
void BM_RerunForNewRobot(benchmark::State& state) {
  const Scan& scan = garageScan(int(state.range(0)));
  const auto analysis = std::make_shared<const ScanAnalysis>(analyseScan(scan, {}, 2));
  SegmentationParams params;
  double width = 0.8;
  for (auto _ : state) {
    params.robot.width = width;
    width = width > 1.0 ? 0.8 : width + 0.05;
    benchmark::DoNotOptimize(rerunForRobot(scan, analysis, params, 2));
  }
}
BENCHMARK(BM_RerunForNewRobot)->Arg(423)->Arg(5556)->Unit(benchmark::kMillisecond);

// What every robot re-run copied while results held the analysis by value (before it was shared):
// one copy of stages 1-4's results, on 76,140 and on 1,000,080 points.
// The bytes of the analysis' per-point and per-cell arrays (the bulk of what a copy moves).
template <typename T>
double bytesOf(const std::vector<T>& values) {
  return double(values.size() * sizeof(T));
}

void BM_CopyAnalysis(benchmark::State& state) {
  const Scan& scan = garageScan(int(state.range(0)));
  const ScanAnalysis analysis = analyseScan(scan, {}, 2);
  for (auto _ : state) {
    ScanAnalysis copy = analysis;
    benchmark::DoNotOptimize(copy.inputs.obstacles.data());
  }
  const MapInputs& inputs = analysis.inputs;
  double bytes = bytesOf(analysis.segments) + bytesOf(analysis.planes.point_plane) +
                 bytesOf(inputs.ground_plane) + bytesOf(inputs.ground_height) +
                 bytesOf(inputs.seam_step) + bytesOf(inputs.ground_spacing) +
                 bytesOf(inputs.obstacles) + bytesOf(inputs.ground_mesh.points) +
                 bytesOf(inputs.ground_mesh.cells) + bytesOf(inputs.ground_mesh.triangles) +
                 bytesOf(analysis.stairs.cell_staircase);
  for (const SupportImage& support : analysis.planes.supports)
    bytes += bytesOf(support.kept);
  state.counters["MB"] = bytes / 1e6;
}
BENCHMARK(BM_CopyAnalysis)->Arg(423)->Arg(5556)->Unit(benchmark::kMillisecond);

// "Can it get there?" on a 76k-point scan: the garage's yard through the 0.9 m door, from the
// robot's own place (the farthest reachable cell, found once).
void BM_GoalQuery(benchmark::State& state) {
  const Scan& scan = garageScan(423);
  const PipelineResult result = runPipeline(scan, {}, 2);
  const TraversabilityMap& map = result.map;
  Eigen::Vector2d goal(map.robot_pose.x, map.robot_pose.y);
  double farthest = -1.0;
  for (int row = 0; row < map.grid.height; ++row)
    for (int column = 0; column < map.grid.width; ++column) {
      if (!map.reach[map.grid.index(column, row)]) continue;
      const Eigen::Vector2d centre = map.grid.centre(column, row);
      const double distance = (centre - goal).norm();
      if (distance > farthest) {
        farthest = distance;
        goal = centre;
      }
    }
  for (auto _ : state)
    benchmark::DoNotOptimize(planPath(map, goal.x(), goal.y()));
  state.counters["reachable_cells"] = double(map.reachable_cells);
  state.counters["goal_distance_m"] = farthest;
}
BENCHMARK(BM_GoalQuery)->Unit(benchmark::kMillisecond);

void BM_Traversability(benchmark::State& state) {
  const Scan& scan = garageScan(423);
  const ScanAnalysis analysis = analyseScan(scan, {}, 2);
  SegmentationParams params;
  params.map.orientations = int(state.range(0));
  for (auto _ : state)
    benchmark::DoNotOptimize(computeTraversability(analysis, params.robot, params.map, 2));
  state.counters["cells"] = double(analysis.inputs.grid.cells());
}
BENCHMARK(BM_Traversability)->Arg(12)->Arg(36)->Unit(benchmark::kMillisecond);

// The target's map size: the outdoor scene (about 12 x 11 m of ground) at 2.5 cm cells is about
// 500 x 430 cells; 36 orientations.
void BM_TraversabilityLargeMap(benchmark::State& state) {
  const Scan& scan = sceneScan("outdoor", 423);
  SegmentationParams params;
  params.map.resolution = 0.025;
  params.map.orientations = 36;
  const ScanAnalysis analysis = analyseScan(scan, params, 2);
  for (auto _ : state)
    benchmark::DoNotOptimize(computeTraversability(analysis, params.robot, params.map, 2));
  state.counters["width"] = analysis.inputs.grid.width;
  state.counters["height"] = analysis.inputs.grid.height;
}
BENCHMARK(BM_TraversabilityLargeMap)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  clearway::keepFreedMemoryForReuse();  // as the applications do
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
