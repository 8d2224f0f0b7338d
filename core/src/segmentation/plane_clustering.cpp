// Stage 2: region growing over segments of neighbouring scan lines. Segments are compared with
// each other until a plane exists, then with the plane, which is refitted every few segments so
// it cannot drift (paper II-B).

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <deque>
#include <numbers>
#include <numeric>
#include <utility>

#include "clearway/segmentation/planes.h"
#include "parallel.h"

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

// However far, rings of one surface are not farther apart than this [m].
constexpr double kLongestRingGap = 3.0;

// Multi-beam rings `lines` apart meet ground below the sensor range^2 / height x step apart: the
// extra distance allowed between two segments there (0 for other sensors, or above the sensor).
double ringGap(const LineSegment& a, const LineSegment& b, const LineNeighbourhood& around,
               int lines) {
  if (around.ring_step <= 0.0) return 0.0;
  // Below this height difference the surface is not ground seen from above [m].
  constexpr double kLowestHeight = 0.3;
  const Eigen::Vector3f up = around.up.cast<float>();
  const double height =
      -std::max(up.dot(a.start + a.end), up.dot(b.start + b.end)) / 2.0;  // sensor above both
  if (height < kLowestHeight) return 0.0;
  const double range = std::max(a.range, b.range);
  return std::min(kLongestRingGap, range * range / height * around.ring_step * lines);
}

// Where a segment's midpoint lies about the sensor's z axis.
struct Bearing {
  double azimuth = 0.0;  // [rad]
  double radius = 0.0;   // horizontal distance from the axis [m]
};

Bearing bearingOf(const LineSegment& segment) {
  const Eigen::Vector3f middle = (segment.start + segment.end) / 2;
  return {std::atan2(double(middle.y()), double(middle.x())),
          std::hypot(double(middle.x()), double(middle.y()))};
}

// One line's segments by the direction of their midpoints about the sensor's z axis, to find
// those that may lie near a given segment without looking at all of them: a multi-beam ring has
// hundreds of segments all round the sensor, and comparing each with every segment of the next
// rings was a fifth of such a frame's plane stages.
class LineByAzimuth {
 public:
  LineByAzimuth(const std::vector<LineSegment>& segments, const std::vector<Bearing>& bearings,
                std::size_t begin, std::size_t end)
      : begin_(begin), end_(end) {
    for (std::size_t j = begin; j < end; ++j) {
      entries_.push_back({bearings[j].azimuth, std::uint32_t(j)});
      longest_ = std::max(longest_, double(segments[j].length()));
    }
    std::sort(entries_.begin(), entries_.end());
  }

  double longest() const { return longest_; }

  // The segments of the line (ascending) whose midpoints may lie within `reach` of a midpoint at
  // `bearing`. Two points at horizontal radii r and r' with directions `delta` apart lie at least
  // max(r, r') sin(delta) apart (at least max(r, r') beyond a right angle): the rest are left out.
  void near(const Bearing& bearing, double reach, std::vector<std::uint32_t>& out) const {
    out.clear();
    if (reach >= bearing.radius) {
      for (std::size_t j = begin_; j < end_; ++j)
        out.push_back(std::uint32_t(j));
      return;
    }
    const double centre = bearing.azimuth;
    const double half = std::asin(reach / bearing.radius) + kAngleSlack;
    auto collect = [&](double from, double to) {
      auto it = std::lower_bound(entries_.begin(), entries_.end(), Entry{from, 0});
      for (; it != entries_.end() && it->azimuth <= to; ++it)
        out.push_back(it->segment);
    };
    const double pi = std::numbers::pi;
    collect(std::max(centre - half, -pi - 1.0), std::min(centre + half, pi + 1.0));
    if (centre - half < -pi) collect(centre - half + 2 * pi, pi + 1.0);  // wrapped
    if (centre + half > pi) collect(-pi - 1.0, centre + half - 2 * pi);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }

 private:
  // atan2 and asin are within a few ulps; this is far beyond them [rad].
  static constexpr double kAngleSlack = 1e-6;
  struct Entry {
    double azimuth;
    std::uint32_t segment;
    bool operator<(const Entry& other) const { return azimuth < other.azimuth; }
  };
  std::vector<Entry> entries_;
  std::size_t begin_, end_;
  double longest_ = 0.0;
};

// Segments of neighbouring lines that look alike: nearly parallel and close.
std::vector<std::vector<std::uint32_t>> similarNeighbours(const std::vector<LineSegment>& segments,
                                                          std::size_t line_count,
                                                          const ClusterParams& params,
                                                          const LineNeighbourhood& around,
                                                          int threads) {
  std::vector<std::size_t> line_begin(line_count + 1, segments.size());
  for (std::size_t i = segments.size(); i-- > 0;)
    line_begin[segments[i].line] = i;
  for (std::size_t l = line_count; l-- > 0;)
    line_begin[l] = std::min(line_begin[l], line_begin[l + 1]);

  // Rings go round the sensor, and their segments are looked up by azimuth; a rotating scanner's
  // fan lies in one vertical half-plane, where the azimuth tells its segments nothing apart.
  const bool rings = around.ring_step > 0.0;
  std::vector<Bearing> bearings(rings ? segments.size() : 0);
  detail::parallelChunks(bearings.size(), threads,
                         [&](std::size_t begin, std::size_t end, std::size_t) {
                           for (std::size_t i = begin; i < end; ++i)
                             bearings[i] = bearingOf(segments[i]);
                         });
  std::vector<LineByAzimuth> by_azimuth;
  if (rings) {
    by_azimuth.reserve(line_count);
    for (std::size_t l = 0; l < line_count; ++l)
      by_azimuth.emplace_back(segments, bearings, line_begin[l], line_begin[l + 1]);
  }
  // The farthest apart two segments' midpoints may lie and still be similar, less the half
  // lengths: `allowed` below at its largest, with a millimetre for the floats' rounding.
  const double farthest_gap = around.ring_step > 0.0 ? kLongestRingGap : 0.0;
  constexpr double kReachSlack = 1e-3;  // [m]

  const double cos_max = std::cos(params.max_angle_deg * std::numbers::pi / 180.0);
  // The similar pairs (i, j), j on a line after i's, found for contiguous parts of the segments
  // side by side; handed to both segments' lists part by part, in the order one thread would
  // (the region growing below reads the lists in order).
  using Pair = std::pair<std::uint32_t, std::uint32_t>;
  constexpr std::size_t kPartsPerThread = 4;  // rings are uneven: a car's side, open road
  detail::PerPart<std::vector<Pair>> pairs(
      detail::chunkCount(segments.size(), threads, kPartsPerThread));
  detail::parallelChunks(
      segments.size(), threads,
      [&](std::size_t begin, std::size_t end, std::size_t part) {
        std::vector<std::uint32_t> candidates;
        for (std::size_t i = begin; i < end; ++i) {
          const LineSegment& a = segments[i];
          for (int step = 1; step <= params.neighbour_lines; ++step) {
            // Wrap around: the last line of a full turn neighbours the first (not of a partial
            // one).
            if (!around.closed_turn && a.line + std::size_t(step) >= line_count) break;
            const std::size_t line = (a.line + std::size_t(step)) % line_count;
            if (line == a.line) break;
            if (rings) {
              const double reach =
                  params.max_distance + std::max(0.0, params.distance_per_metre) * double(a.range) +
                  farthest_gap + (double(a.length()) + by_azimuth[line].longest()) / 2 +
                  kReachSlack;
              by_azimuth[line].near(bearings[i], reach, candidates);
            } else {
              candidates.resize(line_begin[line + 1] - line_begin[line]);
              std::iota(candidates.begin(), candidates.end(), std::uint32_t(line_begin[line]));
            }
            for (const std::uint32_t j : candidates) {
              const LineSegment& b = segments[j];
              if (std::abs(a.direction.dot(b.direction)) < cos_max) continue;
              const double range = std::min(a.range, b.range);
              const double allowed = params.max_distance + params.distance_per_metre * range +
                                     ringGap(a, b, around, step);
              // The segments lie at least this far apart (their midpoints' distance less their
              // half lengths, less a float's rounding): most pairs of a ring's neighbours are
              // ruled out without the exact distance.
              constexpr float kRounding = 1e-4F;  // [m]
              const float apart = (a.start + a.end - b.start - b.end).norm() / 2 -
                                  (a.length() + b.length()) / 2 - kRounding;
              if (apart > allowed || segmentDistance(a, b) > allowed) continue;
              pairs[part].emplace_back(std::uint32_t(i), j);
            }
          }
        }
      },
      kPartsPerThread);
  std::vector<std::vector<std::uint32_t>> neighbours(segments.size());
  for (const std::vector<Pair>& part : pairs)
    for (const auto& [i, j] : part) {
      neighbours[i].push_back(j);
      neighbours[j].push_back(i);
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
                                   const LineNeighbourhood& neighbourhood, int threads) {
  if (segments.empty() || line_count == 0) return {};
  const auto neighbours = similarNeighbours(segments, line_count, params, neighbourhood, threads);
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
