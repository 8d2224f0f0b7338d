// A multi-beam LiDAR frame end to end (issue 14/15: <= 20 ms per 124k-point frame, 2 threads):
// KITTI 000001.bin from CLEARWAY_REAL_DATA_DIR, skipped with a message when the real scans are
// absent. Per-stage times are reported as counters, as BM_Pipeline does.

#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include "clearway/io/scan_io.h"
#include "clearway/pipeline.h"

namespace {

using namespace clearway;

// The frame, loaded once; empty when the real scans are not beside the project.
const std::optional<Scan>& kittiFrame() {
  static const std::optional<Scan> frame = []() -> std::optional<Scan> {
    const std::filesystem::path file =
        std::filesystem::path(CLEARWAY_REAL_DATA_DIR) / "kitti" / "000001.bin";
    if (!std::filesystem::exists(file)) return std::nullopt;
    return loadScan(file);
  }();
  return frame;
}

void BM_MultiBeamFrame(benchmark::State& state) {
  const std::optional<Scan>& scan = kittiFrame();
  if (!scan) {
    state.SkipWithError("kitti/000001.bin not found under " CLEARWAY_REAL_DATA_DIR);
    return;
  }
  const int threads = int(state.range(0));
  std::map<std::string, double> stage_ms;
  for (auto _ : state) {
    const PipelineResult result = runPipeline(*scan, {}, threads);
    for (const StageTiming& stage : result.timings)
      stage_ms[stage.stage] += stage.milliseconds;
  }
  for (const auto& [stage, total] : stage_ms)
    state.counters[stage + "_ms"] = total / double(state.iterations());
  state.counters["points"] = double(scan->size());
}
BENCHMARK(BM_MultiBeamFrame)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

}  // namespace
