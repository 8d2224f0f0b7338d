#include "clearway/pipeline.h"

#include <chrono>
#include <stdexcept>

namespace clearway {
namespace {

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

void checkParams(const SegmentationParams& params) {
  if (const auto reasons = params.validate(); !reasons.empty())
    throw std::invalid_argument("invalid parameters: " + reasons.front());
}

}  // namespace

std::vector<PointClass> classifyPoints(const Scan& scan, const ScanAnalysis& analysis,
                                       const RobotParams&) {
  std::vector<PointClass> classes(scan.size(), PointClass::kNone);
  const auto& point_plane = analysis.planes.point_plane;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!scan.isValid(i)) continue;
    const int plane = i < point_plane.size() ? point_plane[i] : -1;
    if (plane < 0) {
      classes[i] = PointClass::kObstacle;
      continue;
    }
    switch (analysis.planes.planes[std::size_t(plane)].kind) {
      case PlaneKind::kGround:
        classes[i] = PointClass::kGround;
        break;
      case PlaneKind::kWall:
        classes[i] = PointClass::kWall;
        break;
      case PlaneKind::kCeiling:
        classes[i] = PointClass::kCeiling;
        break;
      default:
        classes[i] = PointClass::kObstacle;
        break;
    }
  }
  classifyStairPoints(scan, analysis, classes);
  return classes;
}

PipelineResult rerunForRobot(const Scan& scan, ScanAnalysis analysis,
                             const SegmentationParams& params, int threads,
                             const ProgressCallback& progress) {
  checkParams(params);
  PipelineResult result;
  result.robot = params.robot;
  result.timings = analysis.timings;
  auto start = std::chrono::steady_clock::now();
  result.map = computeTraversability(analysis, params.robot, params.map, threads, progress);
  result.timings.push_back({"traversability", millisecondsSince(start)});
  start = std::chrono::steady_clock::now();
  result.scene = buildSceneGeometry(scan, analysis, result.map, params.robot);
  result.point_classes = classifyPoints(scan, analysis, params.robot);
  result.timings.push_back({"scene", millisecondsSince(start)});
  for (const StageTiming& timing : result.timings)
    result.total_ms += timing.milliseconds;
  result.analysis = std::move(analysis);
  return result;
}

PipelineResult runPipeline(const Scan& scan, const SegmentationParams& params, int threads,
                           const ProgressCallback& progress) {
  checkParams(params);
  auto analysisProgress = [&](double f) { return !progress || progress(0.8 * f); };
  ScanAnalysis analysis = analyseScan(scan, params, threads, analysisProgress);
  auto mapProgress = [&](double f) { return !progress || progress(0.8 + 0.2 * f); };
  return rerunForRobot(scan, std::move(analysis), params, threads, mapProgress);
}

}  // namespace clearway
