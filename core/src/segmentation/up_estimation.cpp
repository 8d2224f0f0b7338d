// Up direction without a pose. A scanner on a robot's arm stands above the floor the robot stands
// on, and nothing is seen below that floor: the floor is a large validated plane with the scanner
// a plausible height above it and (almost) no returns behind it. Walls pass the same test inside
// a closed room, so the plausible up directions compete on the floor area they explain, and the
// estimate is given only when one clearly wins. Floor and ceiling are told apart by what stands on
// the floor: the unassigned returns (furniture, clutter) crowd its side of the room.

#include "clearway/segmentation/up_estimation.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <vector>

namespace clearway {
namespace {

// A floor the robot stands on shows at least this much connected support [m^2].
constexpr double kMinFloorArea = 1.0;
// The scanner rides on the robot's arm: at most this far above the floor it stands on [m].
constexpr double kMaxScannerHeight = 3.0;
// Near-zero offsets leave the side of the plane open (files with their origin at ground level).
constexpr double kGroundLevelOffset = 0.3;
// Returns this far behind a candidate floor (plus range noise) count as "seen below it" [m].
constexpr double kBehindTolerance = 0.15;
constexpr double kBehindTolerancePerMetre = 0.01;
// A floor may hide at most this share of the returns behind it (stairwells down, drains, noise).
constexpr double kMaxBehindFraction = 0.02;
// Directions closer than this are one hypothesis (a floor and a lower floor) [deg].
constexpr double kSameDirectionDeg = 10.0;
// Without clutter to go by, the floor must explain this many times the next direction's area.
constexpr double kAreaDominance = 2.0;
// The scanner must see something this far above itself [m] ...
constexpr double kAboveScanner = 0.3;
// ... in at least this share of its returns.
constexpr double kMinShareAbove = 0.001;
// Returns on no plane (objects, clutter) that make their heights worth a median.
constexpr std::size_t kMinClutterSamples = 30;
// Objects stand on the floor below the arm-carried scanner: their median height over the floor,
// as a share of the scanner's, must be below this (around a wall it is ~1, under a ceiling > 1) ...
constexpr double kMaxFloorClutterRatio = 0.85;
// ... and clearly below that of every other direction.
constexpr double kClutterMargin = 0.75;
// Heights of scanners at ground level are taken as this when forming the ratio [m].
constexpr double kMinRatioHeight = 0.3;
// Every this-many-th valid point is enough to measure shares of the scan.
constexpr std::size_t kSampleStride = 7;

struct Hypothesis {
  Eigen::Vector3d up;
  double height = 0.0;   // of the scanner above the floor [m]
  double area = 0.0;     // floor area this direction explains [m^2]
  double largest = 0.0;  // area of its largest plane, the one `height` belongs to [m^2]
  double clutter_ratio = 0.0;
};

struct Samples {
  std::vector<Eigen::Vector3d> all;
  std::vector<Eigen::Vector3d> unassigned;  // on no validated plane: objects, clutter
};

Samples samplePoints(const Scan& scan, const ValidatedPlanes& planes) {
  Samples samples;
  samples.all.reserve(scan.size() / kSampleStride + 1);
  for (std::size_t i = 0; i < scan.size(); i += kSampleStride) {
    if (!scan.isValid(i)) continue;
    const Eigen::Vector3d p(scan.points[i].x, scan.points[i].y, scan.points[i].z);
    samples.all.push_back(p);
    if (i < planes.point_plane.size() && planes.point_plane[i] < 0) samples.unassigned.push_back(p);
  }
  return samples;
}

double shareAbove(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& up,
                  double level) {
  if (points.empty()) return 0.0;
  std::size_t above = 0;
  for (const Eigen::Vector3d& p : points)
    if (up.dot(p) > level) ++above;
  return double(above) / double(points.size());
}

double medianHeight(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& up,
                    double floor_height) {
  if (points.empty()) return 0.0;
  std::vector<double> heights;
  heights.reserve(points.size());
  for (const Eigen::Vector3d& p : points)
    heights.push_back(up.dot(p) + floor_height);
  std::nth_element(heights.begin(), heights.begin() + long(heights.size() / 2), heights.end());
  return heights[heights.size() / 2];
}

double behindFraction(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& up,
                      double height) {
  if (points.empty()) return 1.0;
  std::size_t behind = 0;
  for (const Eigen::Vector3d& p : points)
    if (up.dot(p) < -height - kBehindTolerance - kBehindTolerancePerMetre * p.norm()) ++behind;
  return double(behind) / double(points.size());
}

}  // namespace

UpEstimate estimateUp(const Scan& scan, const ValidatedPlanes& planes, const GroundParams& params) {
  UpEstimate estimate;
  const Samples samples = samplePoints(scan, planes);
  std::vector<Hypothesis> plausible;
  const double cos_same = std::cos(kSameDirectionDeg * std::numbers::pi / 180.0);
  for (const Plane& plane : planes.planes) {
    if (plane.support_area < kMinFloorArea) continue;
    // n points from the scanner to the plane: up is -n with the scanner `offset` above it; near
    // ground level the other side is possible too.
    std::vector<std::pair<Eigen::Vector3d, double>> sides = {{-plane.normal, plane.offset}};
    if (plane.offset < kGroundLevelOffset) sides.push_back({plane.normal, -plane.offset});
    for (const auto& side : sides) {
      // Named copies: clang 14 lets no lambda capture a structured binding (C++20 allows it).
      const Eigen::Vector3d& up = side.first;
      const double height = side.second;
      if (height > kMaxScannerHeight || height < params.min_scanner_height) continue;
      if (behindFraction(samples.all, up, height) > kMaxBehindFraction) continue;
      // A scan that sees nothing above the scanner cannot tell this floor from a ceiling seen
      // from below (a scanner looking only up).
      if (shareAbove(samples.all, up, kAboveScanner) < kMinShareAbove) continue;
      auto same = std::find_if(plausible.begin(), plausible.end(),
                               [&](const Hypothesis& h) { return h.up.dot(up) > cos_same; });
      if (same == plausible.end()) {
        plausible.push_back({up, height, plane.support_area, plane.support_area});
      } else {
        if (plane.support_area > same->largest) {
          same->up = up;
          same->height = height;
          same->largest = plane.support_area;
        }
        same->area += plane.support_area;
      }
    }
  }
  estimate.hypotheses = int(plausible.size());
  if (plausible.empty()) {
    estimate.reason =
        "the scan has no pose and no large plane lies below the scanner with nothing seen behind "
        "it and something seen above the scanner: give the pose (--pose/--up) or pick the floor";
    return estimate;
  }
  if (plausible.size() == 1) {
    estimate.found = true;
    estimate.up = plausible[0].up;
    estimate.confidence = 1.0;
    return estimate;
  }
  const std::string ambiguous =
      "the scan has no pose and its up direction is ambiguous: give the pose (--pose/--up) or "
      "pick the floor";
  std::sort(plausible.begin(), plausible.end(),
            [](const Hypothesis& a, const Hypothesis& b) { return a.area > b.area; });
  const Hypothesis* by_area =
      plausible[0].area >= kAreaDominance * plausible[1].area ? &plausible[0] : nullptr;

  // Several directions would do: the floor is the one things stand on.
  if (samples.unassigned.size() < kMinClutterSamples) {
    if (!by_area) {
      estimate.reason = ambiguous;
      return estimate;
    }
    estimate.found = true;
    estimate.up = by_area->up;
    estimate.confidence = 1.0 - plausible[1].area / plausible[0].area;
    return estimate;
  }
  for (Hypothesis& h : plausible)
    h.clutter_ratio =
        medianHeight(samples.unassigned, h.up, h.height) / std::max(h.height, kMinRatioHeight);
  const auto lowest = std::min_element(
      plausible.begin(), plausible.end(),
      [](const Hypothesis& a, const Hypothesis& b) { return a.clutter_ratio < b.clutter_ratio; });
  double runner_up = std::numeric_limits<double>::infinity();
  for (const Hypothesis& h : plausible)
    if (&h != &*lowest) runner_up = std::min(runner_up, h.clutter_ratio);
  const bool clear_by_clutter = lowest->clutter_ratio <= kMaxFloorClutterRatio &&
                                lowest->clutter_ratio <= kClutterMargin * runner_up;
  const bool area_disagrees = by_area && by_area != &*lowest;
  if (!clear_by_clutter || area_disagrees) {
    estimate.reason = ambiguous;
    return estimate;
  }
  estimate.found = true;
  estimate.up = lowest->up;
  estimate.confidence = std::clamp(1.0 - lowest->clutter_ratio / runner_up, 0.0, 1.0);
  return estimate;
}

}  // namespace clearway
