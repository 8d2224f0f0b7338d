#include "clearway/pipeline.h"

#include <algorithm>
#include <chrono>
#include <opencv2/core/utility.hpp>
#include <sstream>
#include <stdexcept>

#include "segmentation/parallel.h"

namespace clearway {
namespace {

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// OpenCV's own thread count (its morphology in plane validation and in the traversability stage)
// is process-wide and defaults to every core: for one run it is the caller's `threads`, and what
// it was before afterwards. Set only when it differs: setting it restarts OpenCV's pool.
class OpenCvThreads {
 public:
  explicit OpenCvThreads(int threads) : previous_(cv::getNumThreads()) {
    if (std::max(threads, 1) != previous_) cv::setNumThreads(std::max(threads, 1));
  }
  ~OpenCvThreads() {
    if (cv::getNumThreads() != previous_) cv::setNumThreads(previous_);
  }
  OpenCvThreads(const OpenCvThreads&) = delete;
  OpenCvThreads& operator=(const OpenCvThreads&) = delete;

 private:
  int previous_;
};

// Stages 1-4 take most of a run's time: their share of the progress bar.
constexpr double kAnalysisProgressShare = 0.8;

void checkParams(const SegmentationParams& params) {
  if (const auto reasons = params.validate(); !reasons.empty())
    throw std::invalid_argument("invalid parameters: " + reasons.front());
}

// Why the result shows nothing traversable: the analysis' reason, or, for a scan whose ground is
// everywhere too sparse for this robot to show anything green, that (nothing is wrong with the
// ground found, but no cell can be vouched for).
std::string sparseOrBlockedReason(const TraversabilityMap& map, const RobotParams& robot,
                                  const ScanAnalysis& analysis) {
  if (!analysis.ground_found || map.counts[std::size_t(CellLabel::kTraversable)] > 0)
    return analysis.reason;
  const auto sparse =
      std::count(map.reasons.begin(), map.reasons.end(), std::uint8_t(CellReason::kSparse));
  const auto above_view =
      std::count(map.reasons.begin(), map.reasons.end(), std::uint8_t(CellReason::kAboveView));
  std::ostringstream reason;
  if (above_view > 0 && above_view >= sparse) {
    reason << "nothing traversable: on " << above_view
           << " cells where the robot fits, its band up to its height (" << robot.height
           << " m) was above everything the scanner looked at, so an overhang there would never "
              "have been measured (tilt the scanner to look higher, or raise it)";
    return reason.str();
  }
  if (sparse == 0) {
    // Ground was found, and no cell is green for a reason of the map's own: say which.
    const std::size_t careful = map.counts[std::size_t(CellLabel::kCareful)] +
                                map.counts[std::size_t(CellLabel::kObstacle)];
    reason << "nothing traversable: the robot's box (" << robot.width << " x " << robot.length
           << " m) fits with room to spare nowhere on the ground seen; unobserved gaps, obstacles "
              "and steps cut it into patches smaller than the robot ("
           << careful << " cells fit only with care)";
    return reason.str();
  }
  reason << "scan too sparse to show anything traversable: on " << sparse
         << " cells the ground samples are so far apart that an obstacle taller than the step ("
         << robot.max_step << " m) could hide between them (scan with more lines)";
  return reason.str();
}

// The reason, after what the loader could not work out (ScanMetadata::caution) when there is
// one: a reason drawn from a scan misread names the wrong cause on its own.
std::string resultReason(const TraversabilityMap& map, const RobotParams& robot,
                         const ScanAnalysis& analysis, const std::string& caution) {
  const std::string reason = sparseOrBlockedReason(map, robot, analysis);
  if (caution.empty() || reason.empty()) return reason;
  return caution + "; " + reason;
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

PipelineResult rerunForRobot(const Scan& scan, std::shared_ptr<const ScanAnalysis> analysis,
                             const SegmentationParams& params, int threads,
                             const ProgressCallback& progress) {
  if (!analysis) throw std::invalid_argument("rerunForRobot: no scan analysis to re-run on");
  checkParams(params);
  const OpenCvThreads opencv_threads(threads);
  PipelineResult result;
  result.robot = params.robot;
  result.timings = analysis->timings;
  auto start = std::chrono::steady_clock::now();
  result.map = computeTraversability(*analysis, params.robot, params.map, threads, progress);
  result.timings.push_back({"traversability", millisecondsSince(start)});
  result.reason = resultReason(result.map, params.robot, *analysis, scan.metadata.caution);
  start = std::chrono::steady_clock::now();
  // The point classes do not depend on the map: beside the scene's parts.
  detail::parallelTasks(
      {[&] {
         result.scene = buildSceneGeometry(scan, *analysis, result.map, params.robot, threads);
       },
       [&] { result.point_classes = classifyPoints(scan, *analysis, params.robot); }},
      threads);
  result.timings.push_back({"scene", millisecondsSince(start)});
  for (const StageTiming& timing : result.timings)
    result.total_ms += timing.milliseconds;
  result.analysis = std::move(analysis);
  return result;
}

PipelineResult runPipeline(const Scan& scan, const SegmentationParams& params, int threads,
                           const ProgressCallback& progress) {
  checkParams(params);
  const OpenCvThreads opencv_threads(threads);
  auto analysisProgress = [&](double f) {
    return !progress || progress(kAnalysisProgressShare * f);
  };
  auto analysis =
      std::make_shared<const ScanAnalysis>(analyseScan(scan, params, threads, analysisProgress));
  auto mapProgress = [&](double f) {
    return !progress || progress(kAnalysisProgressShare + (1.0 - kAnalysisProgressShare) * f);
  };
  return rerunForRobot(scan, std::move(analysis), params, threads, mapProgress);
}

}  // namespace clearway
