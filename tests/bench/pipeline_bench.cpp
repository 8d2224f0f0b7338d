// Google Benchmark micro-benchmarks of the pipeline on simulated RoSi scans (docs/PERFORMANCE.md).
// Speed is measured here, never asserted in a test. Run: build/tests/bench/clearway_bench

#include <benchmark/benchmark.h>

#include <map>

#include "clearway/pipeline.h"
#include "clearway/sim/builtin_scenes.h"
#include "clearway/sim/rosi_simulator.h"

namespace {

using namespace clearway;

// Simulated garage scans, made once per line count: 80 lines = 14,400 points, 423 = 76,140.
const Scan& garageScan(int lines) {
  static std::map<int, Scan> scans;
  auto it = scans.find(lines);
  if (it == scans.end()) {
    const sim::Scene scene = *sim::builtinScene("garage");
    sim::SensorModel sensor;
    sensor.lines = lines;
    it = scans.emplace(lines, sim::simulateRosi(scene, sensor, sim::defaultPlacement(scene)).scan)
             .first;
  }
  return it->second;
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

// What a robot slider move costs: stages 5-6 on a cached analysis.
void BM_RerunForNewRobot(benchmark::State& state) {
  const Scan& scan = garageScan(423);
  const ScanAnalysis analysis = analyseScan(scan, {}, 2);
  SegmentationParams params;
  double width = 0.8;
  for (auto _ : state) {
    params.robot.width = width;
    width = width > 1.0 ? 0.8 : width + 0.05;
    benchmark::DoNotOptimize(rerunForRobot(scan, analysis, params, 2));
  }
}
BENCHMARK(BM_RerunForNewRobot)->Unit(benchmark::kMillisecond);

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

}  // namespace

BENCHMARK_MAIN();
