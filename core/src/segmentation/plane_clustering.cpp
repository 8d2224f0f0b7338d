// Stage 2: region growing over segments of neighbouring scan lines. Segments are compared with
// each other until a plane exists, then with the plane, which is refitted every few segments so
// it cannot drift (paper II-B).

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <deque>
#include <numbers>
#include <numeric>

#include "clearway/segmentation/planes.h"

namespace clearway {
namespace {

double pointToSegment(const Eigen::Vector3f& p, const LineSegment& s) {
  const Eigen::Vector3f d = s.end - s.start;
  const float length_squared = d.squaredNorm();
  const float t =
      length_squared > 0 ? std::clamp((p - s.start).dot(d) / length_squared, 0.0F, 1.0F) : 0.0F;
  return (p - (s.start + t * d)).norm();
}

double segmentDistance(const LineSegment& a, const LineSegment& b) {
  return std::min({pointToSegment(a.start, b), pointToSegment(a.end, b), pointToSegment(b.start, a),
                   pointToSegment(b.end, a)});
}

// Multi-beam rings `lines` apart meet ground below the sensor range^2 / height x step apart: the
// extra distance allowed between two segments there (0 for other sensors, or above the sensor).
double ringGap(const LineSegment& a, const LineSegment& b, const LineNeighbourhood& around,
               int lines) {
  if (around.ring_step <= 0.0) return 0.0;
  // Below this height difference the surface is not ground seen from above [m].
  constexpr double kLowestHeight = 0.3;
  // However far, rings of one surface are not farther apart than this [m].
  constexpr double kLongestGap = 3.0;
  const Eigen::Vector3f up = around.up.cast<float>();
  const double height =
      -std::max(up.dot(a.start + a.end), up.dot(b.start + b.end)) / 2.0;  // sensor above both
  if (height < kLowestHeight) return 0.0;
  const double range = std::max(a.range, b.range);
  return std::min(kLongestGap, range * range / height * around.ring_step * lines);
}

// Segments of neighbouring lines that look alike: nearly parallel and close.
std::vector<std::vector<std::uint32_t>> similarNeighbours(const std::vector<LineSegment>& segments,
                                                          std::size_t line_count,
                                                          const ClusterParams& params,
                                                          const LineNeighbourhood& around) {
  std::vector<std::size_t> line_begin(line_count + 1, segments.size());
  for (std::size_t i = segments.size(); i-- > 0;)
    line_begin[segments[i].line] = i;
  for (std::size_t l = line_count; l-- > 0;)
    line_begin[l] = std::min(line_begin[l], line_begin[l + 1]);

  const double cos_max = std::cos(params.max_angle_deg * std::numbers::pi / 180.0);
  std::vector<std::vector<std::uint32_t>> neighbours(segments.size());
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const LineSegment& a = segments[i];
    for (int step = 1; step <= params.neighbour_lines; ++step) {
      // Wrap around: the last line of a full turn neighbours the first (not of a partial one).
      if (!around.closed_turn && a.line + std::size_t(step) >= line_count) break;
      const std::size_t line = (a.line + std::size_t(step)) % line_count;
      if (line == a.line) break;
      for (std::size_t j = line_begin[line]; j < line_begin[line + 1]; ++j) {
        const LineSegment& b = segments[j];
        if (std::abs(a.direction.dot(b.direction)) < cos_max) continue;
        const double range = std::min(a.range, b.range);
        const double allowed =
            params.max_distance + params.distance_per_metre * range + ringGap(a, b, around, step);
        // The segments lie at least this far apart (their midpoints' distance less their half
        // lengths, less a float's rounding): most pairs of a ring's neighbours are ruled out
        // without the exact distance.
        constexpr float kRounding = 1e-4F;  // [m]
        const float apart = (a.start + a.end - b.start - b.end).norm() / 2 -
                            (a.length() + b.length()) / 2 - kRounding;
        if (apart > allowed || segmentDistance(a, b) > allowed) continue;
        neighbours[i].push_back(std::uint32_t(j));
        neighbours[j].push_back(std::uint32_t(i));
      }
    }
  }
  return neighbours;
}

// True once the region's points span a plane rather than a line.
bool spansPlane(const PointMoments& moments) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  // Closed form for 3 x 3, eigenvalues only: this runs each time a segment joins a region that
  // does not span a plane yet (a multi-beam ring's segments stay parallel for metres).
  solver.computeDirect(moments.covariance(), Eigen::EigenvaluesOnly);
  const Eigen::Vector3d lambda = solver.eigenvalues();
  return lambda[1] > 1e-4 && lambda[0] < 0.05 * lambda[1];
}

bool segmentOnPlane(const LineSegment& s, const Plane& plane, const ClusterParams& params,
                    double sin_max_angle) {
  const double tolerance = params.plane_distance + params.plane_distance_per_metre * s.range;
  return std::abs(plane.signedDistance(s.start.cast<double>())) <= tolerance &&
         std::abs(plane.signedDistance(s.end.cast<double>())) <= tolerance &&
         std::abs(plane.normal.dot(s.direction.cast<double>())) <= sin_max_angle;
}

}  // namespace

const char* planeKindName(PlaneKind kind) {
  switch (kind) {
    case PlaneKind::kGround:
      return "ground";
    case PlaneKind::kWall:
      return "wall";
    case PlaneKind::kCeiling:
      return "ceiling";
    case PlaneKind::kOther:
      return "other";
    case PlaneKind::kUnknown:
      break;
  }
  return "unknown";
}

Plane fitPlane(const PointMoments& moments) {
  Plane plane;
  plane.moments = moments;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(
      moments.covariance());  // closed form for 3 x 3: much faster than the iterative solver
  plane.normal = solver.eigenvectors().col(0).normalized();
  plane.offset = plane.normal.dot(moments.mean());
  if (plane.offset < 0) {
    plane.normal = -plane.normal;
    plane.offset = -plane.offset;
  }
  plane.rms = std::sqrt(std::max(0.0, solver.eigenvalues()[0]));
  return plane;
}

std::vector<Plane> clusterSegments(const std::vector<LineSegment>& segments, std::size_t line_count,
                                   const ClusterParams& params,
                                   const LineNeighbourhood& neighbourhood) {
  if (segments.empty() || line_count == 0) return {};
  const auto neighbours = similarNeighbours(segments, line_count, params, neighbourhood);
  const double sin_max_angle = std::sin(params.max_angle_deg * std::numbers::pi / 180.0);

  // Longest segments seed first: they carry the most reliable direction.
  std::vector<std::uint32_t> order(segments.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return segments[a].length() > segments[b].length();
  });

  std::vector<std::int32_t> owner(segments.size(), -1);
  std::vector<bool> seeded(segments.size(), false);
  std::vector<Plane> planes;
  for (std::uint32_t seed : order) {
    if (owner[seed] >= 0 || seeded[seed]) continue;
    seeded[seed] = true;
    const std::int32_t region_id = std::int32_t(planes.size());
    std::vector<std::uint32_t> region = {seed};
    owner[seed] = region_id;
    PointMoments moments = segments[seed].moments;
    Plane plane;
    bool has_plane = false;
    int since_refit = 0;
    std::deque<std::uint32_t> frontier = {seed};
    while (!frontier.empty()) {
      const std::uint32_t current = frontier.front();
      frontier.pop_front();
      for (std::uint32_t next : neighbours[current]) {
        if (owner[next] >= 0) continue;
        if (has_plane && !segmentOnPlane(segments[next], plane, params, sin_max_angle)) continue;
        owner[next] = region_id;
        region.push_back(next);
        frontier.push_back(next);
        moments += segments[next].moments;
        ++since_refit;
        if ((!has_plane && region.size() >= 3 && spansPlane(moments)) ||
            (has_plane && since_refit >= params.refit_every)) {
          plane = fitPlane(moments);
          has_plane = true;
          since_refit = 0;
        }
      }
    }
    if (int(region.size()) < params.min_segments || !has_plane) {
      for (std::uint32_t s : region)
        owner[s] = -1;  // free for other regions
      continue;
    }
    Plane final_plane = fitPlane(moments);
    // A region that grew along parallel segments before they spanned a plane (the rings of a
    // multi-beam sensor are parallel for many metres) can take in segments no plane holds: its
    // points scatter about the fit more than a segment may lie off a plane to join it.
    const double mean_range = final_plane.moments.mean().norm();
    if (final_plane.rms > params.plane_distance + params.plane_distance_per_metre * mean_range) {
      for (std::uint32_t s : region)
        owner[s] = -1;
      continue;
    }
    final_plane.segments = std::move(region);
    planes.push_back(std::move(final_plane));
  }

  // Coplanar clusters (a floor split by an obstacle, a yard seen through a door) become one.
  const double cos_merge = std::cos(params.merge_angle_deg * std::numbers::pi / 180.0);
  for (bool merged_any = true; merged_any;) {
    merged_any = false;
    for (std::size_t i = 0; i < planes.size() && !merged_any; ++i) {
      for (std::size_t j = i + 1; j < planes.size(); ++j) {
        if (planes[i].normal.dot(planes[j].normal) < cos_merge) continue;
        if (std::abs(planes[i].offset - planes[j].offset) > params.merge_distance) continue;
        PointMoments moments = planes[i].moments;
        moments += planes[j].moments;
        Plane merged = fitPlane(moments);
        if (merged.rms > params.plane_distance) continue;
        merged.segments = planes[i].segments;
        merged.segments.insert(merged.segments.end(), planes[j].segments.begin(),
                               planes[j].segments.end());
        planes[i] = std::move(merged);
        planes.erase(planes.begin() + std::ptrdiff_t(j));
        merged_any = true;
        break;
      }
    }
  }
  return planes;
}

}  // namespace clearway
