#include "clearway/segmentation/scan_analysis.h"

#include <chrono>

namespace clearway {
namespace {

// Fewer valid points than this cannot carry a trustworthy ground estimate.
constexpr std::size_t kMinValidPoints = 500;

class StageClock {
 public:
  explicit StageClock(std::vector<StageTiming>& timings) : timings_(timings) {}
  void stop(const std::string& stage) {
    const auto now = std::chrono::steady_clock::now();
    timings_.push_back({stage, std::chrono::duration<double, std::milli>(now - start_).count()});
    start_ = now;
  }

 private:
  std::vector<StageTiming>& timings_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace

ScanAnalysis analyseScan(const Scan& scan, const SegmentationParams& params, int threads,
                         const ProgressCallback& progress) {
  ScanAnalysis analysis;
  analysis.scan_points = scan.size();
  analysis.valid_points = scan.validCount();
  analysis.up = upDirection(scan);
  if (analysis.valid_points < kMinValidPoints) {
    analysis.reason = "scan too sparse: " + std::to_string(analysis.valid_points) +
                      " valid points (at least " + std::to_string(kMinValidPoints) + " needed)";
    analysis.planes.point_plane.assign(scan.size(), -1);
    return analysis;
  }
  StageClock clock(analysis.timings);
  auto stageProgress = [&](double from, double to) -> ProgressCallback {
    if (!progress) return {};
    return [&, from, to](double fraction) { return progress(from + (to - from) * fraction); };
  };

  analysis.segments = detectLineSegments(scan, params.lines, threads, stageProgress(0.0, 0.4));
  clock.stop("lines");
  reportProgress(progress, 0.4);

  std::vector<Plane> candidates =
      clusterSegments(analysis.segments, scan.lines.size(), params.clustering);
  analysis.candidate_planes = candidates.size();
  clock.stop("clustering");
  reportProgress(progress, 0.6);

  analysis.planes = validatePlanes(scan, std::move(candidates), params.validation, threads);
  clock.stop("validation");
  reportProgress(progress, 0.8);

  selectGround(analysis, params.ground);
  clock.stop("ground");
  reportProgress(progress, 0.85);

  if (analysis.ground_found)
    analysis.stairs.staircases = detectStairs(scan, analysis.map_from_scanner, params.stairs);
  clock.stop("stairs");

  prepareMapInputs(scan, params, analysis);
  analysis.stairs.cell_staircase = staircaseCells(analysis.stairs.staircases, analysis.inputs.grid);
  clock.stop("map_inputs");
  reportProgress(progress, 1.0);
  return analysis;
}

}  // namespace clearway
