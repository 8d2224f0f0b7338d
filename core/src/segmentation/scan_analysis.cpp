#include "clearway/segmentation/scan_analysis.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <optional>

#include "clearway/segmentation/up_estimation.h"
#include "clearway/traversability/ground_density.h"
#include "parallel.h"
#include "ring_ground.h"
#include "ring_support.h"

namespace clearway {
namespace {

// Fewer valid points than this cannot carry a trustworthy ground estimate.
constexpr std::size_t kMinValidPoints = 500;
// A large plane's area extends over gaps between its lines this wide [m]: two support cells for a
// RoSi, whose lines stay close; the far rings of a multi-beam sensor on the ground lie up to a few
// metres apart (1.6 m at 20 m for a Velodyne HDL-64E 1.7 m up).
constexpr double kLineGrowthGap = 0.4;
constexpr double kRingGrowthGap = 2.0;
// A multi-beam sensor sees a road out to 20 m and more, where its range noise and the road's own
// camber and slope changes spread the support over more than the flat band: it widens by this
// much per metre (0.15 m at 20 m), so the road is supported as a real plane is, crowding inside.
constexpr double kRingSupportPerMetre = 0.005;

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

// Where the scan's own pose came from (a pose read with the file leaves it kNone), or kNone.
PoseSource givenPoseSource(const Scan& scan) {
  if (!scan.sensor_pose) return PoseSource::kNone;
  return scan.pose_source == PoseSource::kNone ? PoseSource::kFile : scan.pose_source;
}

}  // namespace

ScanAnalysis analyseScan(const Scan& scan, const SegmentationParams& params, int threads,
                         const ProgressCallback& progress) {
  ScanAnalysis analysis;
  StageClock clock(analysis.timings);
  analysis.scan_points = scan.size();
  analysis.valid_points = scan.validCount();
  analysis.up = upDirection(scan);
  analysis.sensor = describeSensor(scan, threads);
  clock.stop("sensor");
  if (analysis.valid_points < kMinValidPoints) {
    analysis.reason = "scan too sparse: " + std::to_string(analysis.valid_points) +
                      " valid points (at least " + std::to_string(kMinValidPoints) + " needed)";
    analysis.planes.point_plane.assign(scan.size(), -1);
    // What the pose is said of the scan as it is for any other (report.json said "none" with a
    // confidence of 1 where the console said "pose: file").
    analysis.pose_source = givenPoseSource(scan);
    analysis.up_confidence = scan.sensor_pose ? 1.0 : 0.0;
    return analysis;
  }
  auto stageProgress = [&](double from, double to) -> ProgressCallback {
    if (!progress) return {};
    return [&, from, to](double fraction) { return progress(from + (to - from) * fraction); };
  };

  analysis.segments = detectLineSegments(scan, params.lines, threads, stageProgress(0.0, 0.4));
  clock.stop("lines");
  reportProgress(progress, 0.4);

  const bool multi_beam = analysis.sensor.kind == SensorKind::kMultiBeam;
  LineNeighbourhood neighbourhood;
  neighbourhood.closed_turn = analysis.sensor.closed_turn;
  neighbourhood.ring_step = multi_beam ? analysis.sensor.between_line_step : 0.0;
  neighbourhood.up = analysis.up;
  std::vector<Plane> candidates = clusterSegments(analysis.segments, scan.lines.size(),
                                                  params.clustering, neighbourhood, threads);
  analysis.candidate_planes = candidates.size();
  clock.stop("clustering");
  reportProgress(progress, 0.6);

  SensorSpread spread;
  spread.growth_gap = multi_beam ? kRingGrowthGap : kLineGrowthGap;
  spread.support_per_metre = multi_beam ? kRingSupportPerMetre : 0.0;
  spread.local_crowding = multi_beam;
  spread.own_segments = multi_beam ? &analysis.segments : nullptr;
  if (multi_beam) {
    const std::vector<double>& elevation = analysis.sensor.line_angle;
    for (std::size_t line = 0; line < elevation.size(); ++line)
      if (std::isfinite(elevation[line])) spread.rings_by_elevation.push_back(line);
    std::sort(spread.rings_by_elevation.begin(), spread.rings_by_elevation.end(),
              [&](std::size_t a, std::size_t b) { return elevation[a] < elevation[b]; });
    spread.ring_azimuth_step = analysis.sensor.along_line_step;
    // Worked out once: the validation's support between rings and the ground followed outward.
    spread.ring_layout = std::make_shared<const detail::RingLayout>(
        detail::ringLayout(scan, spread.rings_by_elevation, spread.ring_azimuth_step, threads));
  }
  analysis.planes = validatePlanes(scan, std::move(candidates), params.validation, threads, spread);
  clock.stop("validation");
  reportProgress(progress, 0.8);

  if (scan.sensor_pose) {
    analysis.pose_source = givenPoseSource(scan);
    if (scan.pose_source == PoseSource::kSidecar) {
      const SensorPose& pose = *scan.sensor_pose;
      Eigen::Isometry3d robot_from_scanner = Eigen::Isometry3d::Identity();
      for (int r = 0; r < 3; ++r) {
        robot_from_scanner.translation()[r] = pose.position[std::size_t(r)];
        for (int c = 0; c < 3; ++c)
          robot_from_scanner.linear()(r, c) = pose.rotation[std::size_t(3 * r + c)];
      }
      analysis.robot_from_scanner = robot_from_scanner;
    }
    selectGround(analysis, params.ground);
  } else if (params.ground.estimate_up == 0) {
    analysis.up_confidence = 0.0;  // no up direction was given or estimated
    analysis.reason =
        "the scan has no pose and estimating its up direction is off (--up none): give the pose "
        "(--pose/--up) or pick the floor";
  } else {
    const UpEstimate estimate = estimateUp(scan, analysis.planes, params.ground);
    analysis.pose_source = PoseSource::kEstimated;
    analysis.up_confidence = estimate.confidence;
    if (estimate.found) {
      analysis.up = estimate.up;
      selectGround(analysis, params.ground);
    } else {
      // A scan with no line neighbours or no plane at all says so: that, not the missing pose, is
      // what the operator must change.
      analysis.reason = analysis.sensor.lines < 2 || analysis.planes.planes.empty()
                            ? noGroundReason(analysis, params.ground, /*up_known=*/false)
                            : estimate.reason;
    }
  }
  // The staircase search needs only the map frame, fixed from here on: it runs beside the
  // ground's last steps.
  std::vector<Staircase> staircases;
  std::optional<detail::BackgroundTask> stairs_search;
  if (analysis.ground_found)
    stairs_search.emplace(
        [&scan, &staircases, &params, map_from_scanner = analysis.map_from_scanner] {
          staircases = detectStairs(scan, map_from_scanner, params.stairs);
        },
        threads);
  if (multi_beam) absorbGroundPatches(scan, params.validation, spread, analysis);
  // Any sensor: ground is the lowest surface in its column (a table top is not).
  dropGroundOverLowerReturns(scan, params.robot.max_step, params.ground.max_slope_deg, analysis,
                             threads);
  if (multi_beam) {
    dropUnreachableGround(scan, params.robot.max_step, params.robot.width, analysis);
    if (analysis.ground_found) {
      detail::OutwardGroundLimits limits;
      limits.off_plane = params.robot.max_step;
      limits.per_metre = kRingSupportPerMetre;
      limits.max_slope = std::tan(params.ground.max_slope_deg * std::numbers::pi / 180.0);
      detail::followGroundOutward(scan, spread.rings_by_elevation, *spread.ring_layout,
                                  analysis.planes.planes, analysis.ground_planes, limits,
                                  analysis.planes.point_plane);
    }
  }
  clock.stop("ground");
  reportProgress(progress, 0.85);

  if (stairs_search) {
    stairs_search->join();
    analysis.stairs.staircases = std::move(staircases);
  }
  clock.stop("stairs");  // what is left of the search once the ground is done

  if (multi_beam && analysis.ground_found) {
    // A multi-beam frame reaches 80 m and more, but its rings vouch for the ground only out to
    // where an obstacle taller than the robot's step could no longer hide between them: farther
    // cells could only ever be "too sparse". The map stops there, plus the robot's circumscribed
    // radius so that its box can stand on the last vouched cells in every orientation.
    SegmentationParams map_params = params;
    const double height = analysis.map_from_scanner.translation().z();
    const double box_radius = std::hypot(params.robot.width, params.robot.length) / 2;
    map_params.map.max_extent =
        std::min(params.map.max_extent,
                 vouchedGroundRange(analysis.sensor, height, params.robot.max_step) + box_radius);
    analysis.inputs = prepareMapInputs(scan, map_params, analysis, threads);
  } else {
    analysis.inputs = prepareMapInputs(scan, params, analysis, threads);
  }
  analysis.stairs.cell_staircase = staircaseCells(analysis.stairs.staircases, analysis.inputs.grid);
  clock.stop("map_inputs");
  reportProgress(progress, 1.0);
  return analysis;
}

}  // namespace clearway
