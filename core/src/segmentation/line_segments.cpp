#include "clearway/segmentation/line_segments.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>

#include "parallel.h"

namespace clearway {
namespace {

Eigen::Vector3d at(const Scan& scan, std::uint32_t i) {
  const Point3f& p = scan.points[i];
  return {p.x, p.y, p.z};
}

double rangeOf(const Eigen::Vector3d& p) {
  return p.norm();
}

// Least-squares line through the points; end points are the first and last points projected.
bool makeSegment(const Scan& scan, std::uint32_t line, const std::vector<std::uint32_t>& indices,
                 const LineParams& params, LineSegment& segment) {
  if (int(indices.size()) < params.min_points) return false;
  PointMoments moments;
  double range_sum = 0.0;
  for (std::uint32_t i : indices) {
    const Eigen::Vector3d p = at(scan, i);
    moments.add(p);
    range_sum += rangeOf(p);
  }
  const Eigen::Vector3d mean = moments.mean();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(
      moments.covariance());  // closed form for 3 x 3: much faster than the iterative solver
  Eigen::Vector3d direction = solver.eigenvectors().col(2);
  const Eigen::Vector3d first = at(scan, indices.front()), last = at(scan, indices.back());
  if (direction.dot(last - first) < 0) direction = -direction;
  const Eigen::Vector3d start = mean + direction * direction.dot(first - mean);
  const Eigen::Vector3d end = mean + direction * direction.dot(last - mean);
  if ((end - start).norm() < params.min_length) return false;
  segment.line = line;
  segment.first = indices.front();
  segment.last = indices.back();
  segment.start = start.cast<float>();
  segment.end = end.cast<float>();
  segment.direction = direction.cast<float>();
  segment.range = float(range_sum / double(indices.size()));
  segment.moments = moments;
  return true;
}

double splitThreshold(const LineParams& params, const Eigen::Vector3d& p) {
  return params.max_deviation + params.deviation_per_metre * rangeOf(p);
}

// Runs of valid points without large gaps, in line order.
std::vector<std::vector<std::uint32_t>> validRuns(const Scan& scan, const ScanLine& line,
                                                  const LineParams& params) {
  std::vector<std::vector<std::uint32_t>> runs;
  std::vector<std::uint32_t> run;
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  for (std::size_t i = line.first; i < line.first + line.count; ++i) {
    if (!scan.isValid(i)) continue;
    const Eigen::Vector3d p = at(scan, std::uint32_t(i));
    if (!run.empty() &&
        (p - previous).norm() > params.max_gap + params.gap_per_metre * rangeOf(p)) {
      runs.push_back(std::move(run));
      run.clear();
    }
    run.push_back(std::uint32_t(i));
    previous = p;
  }
  if (!run.empty()) runs.push_back(std::move(run));
  return runs;
}

// A run's points, converted once, with each point's squared split threshold (it grows with range).
struct RunGeometry {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> threshold_squared;
};

RunGeometry runGeometry(const Scan& scan, const std::vector<std::uint32_t>& run,
                        const LineParams& params) {
  RunGeometry geometry;
  geometry.points.reserve(run.size());
  geometry.threshold_squared.reserve(run.size());
  for (std::uint32_t i : run) {
    const Eigen::Vector3d p = at(scan, i);
    const double threshold = splitThreshold(params, p);
    geometry.points.push_back(p);
    geometry.threshold_squared.push_back(threshold * threshold);
  }
  return geometry;
}

// The point of run[begin..end] farthest from the chord run[begin] -> run[end], relative to its
// threshold; `relative_excess` > 1 means the run must be split there. No square roots in the loop.
std::size_t farthestFromChord(const RunGeometry& run, std::size_t begin, std::size_t end,
                              double& relative_excess) {
  const Eigen::Vector3d& a = run.points[begin];
  const Eigen::Vector3d chord = run.points[end] - a;
  const double chord_squared = chord.squaredNorm();
  std::size_t farthest = begin;
  double worst = 0.0;
  for (std::size_t k = begin + 1; k < end; ++k) {
    const Eigen::Vector3d offset = run.points[k] - a;
    const double distance_squared = chord_squared > 1e-18
                                        ? chord.cross(offset).squaredNorm() / chord_squared
                                        : offset.squaredNorm();
    const double ratio = distance_squared / run.threshold_squared[k];
    if (ratio > worst) {
      worst = ratio;
      farthest = k;
    }
  }
  relative_excess = std::sqrt(worst);
  return farthest;
}

void splitAndMergeLine(const Scan& scan, std::uint32_t line_index, const LineParams& params,
                       std::vector<LineSegment>& out) {
  for (const auto& run : validRuns(scan, scan.lines[line_index], params)) {
    if (int(run.size()) < params.min_points) continue;
    const RunGeometry geometry = runGeometry(scan, run, params);
    // Split: a stack of [begin, end] ranges of the run.
    std::vector<std::pair<std::size_t, std::size_t>> pieces;
    std::vector<std::pair<std::size_t, std::size_t>> stack = {{0, run.size() - 1}};
    while (!stack.empty()) {
      const auto [begin, end] = stack.back();
      stack.pop_back();
      double excess = 0.0;
      const std::size_t split =
          end > begin + 1 ? farthestFromChord(geometry, begin, end, excess) : begin;
      if (excess > 1.0) {
        stack.push_back({split, end});
        stack.push_back({begin, split});
      } else {
        pieces.push_back({begin, end});
      }
    }
    std::sort(pieces.begin(), pieces.end());
    // Merge: neighbours whose union is still straight (the split can cut a line at a noisy point).
    std::vector<std::pair<std::size_t, std::size_t>> merged;
    for (const auto& piece : pieces) {
      if (!merged.empty() && merged.back().second == piece.first) {
        double excess = 0.0;
        farthestFromChord(geometry, merged.back().first, piece.second, excess);
        if (excess <= 1.0) {
          merged.back().second = piece.second;
          continue;
        }
      }
      merged.push_back(piece);
    }
    for (const auto& [begin, end] : merged) {
      // Shared break points belong to the segment before; the next one starts after it.
      const std::size_t from = begin == 0 ? 0 : begin + 1;
      if (from > end) continue;
      std::vector<std::uint32_t> indices(run.begin() + std::ptrdiff_t(from),
                                         run.begin() + std::ptrdiff_t(end) + 1);
      LineSegment segment;
      if (makeSegment(scan, line_index, indices, params, segment)) out.push_back(segment);
    }
  }
}

// Largest Hough accumulator of one scan line [cells of 2 bytes]: 32 MB per thread.
constexpr std::size_t kMaxHoughCells = std::size_t(16) << 20;

// The paper's method: a Hough transform on the scan line's own plane (II-A), done on the point
// set rather than a rasterised image (same accumulator, no image to draw).
void houghLine(const Scan& scan, std::uint32_t line_index, const LineParams& params,
               std::vector<LineSegment>& out) {
  std::vector<LineSegment> found;
  const ScanLine& line = scan.lines[line_index];
  const double angle_step = params.hough_angle_step_deg * std::numbers::pi / 180.0;
  const int thetas = std::max(1, int(std::lround(std::numbers::pi / angle_step)));
  const double rho_step = params.hough_distance_step;
  // The accumulator spans +-range: one far point (a stray return 100 km away) would make it
  // gigabytes. Points beyond the range the cell budget allows are left out of the vote; they
  // cannot share a line with the scene anyway. Defaults: 180 angles, 0.02 m -> about 890 m.
  const double range_limit = (double(kMaxHoughCells) / double(thetas) - 2.0) * rho_step / 2.0;
  std::vector<std::uint32_t> indices;
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  double max_range = 0.0;
  for (std::size_t i = line.first; i < line.first + line.count; ++i) {
    if (!scan.isValid(i)) continue;
    const Eigen::Vector3d p = at(scan, std::uint32_t(i));
    if (!(p.norm() <= range_limit)) continue;
    indices.push_back(std::uint32_t(i));
    scatter += p * p.transpose();
    max_range = std::max(max_range, p.norm());
  }
  if (int(indices.size()) < params.min_points) return;
  // The line's plane passes through the sensor: with beta known it is the paper's rotation by
  // -beta; otherwise the plane through the origin that fits the line best.
  Eigen::Vector3d u_axis, v_axis;
  if (std::isfinite(line.beta)) {
    u_axis = {std::cos(line.beta), std::sin(line.beta), 0.0};
    v_axis = Eigen::Vector3d::UnitZ();
  } else {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
    solver.computeDirect(scatter);  // closed form for 3 x 3: much faster than the iterative solver
    u_axis = solver.eigenvectors().col(2);
    v_axis = solver.eigenvectors().col(1);
  }
  std::vector<Eigen::Vector2d> uv(indices.size());
  for (std::size_t k = 0; k < indices.size(); ++k) {
    const Eigen::Vector3d p = at(scan, indices[k]);
    uv[k] = {p.dot(u_axis), p.dot(v_axis)};
  }
  const int rhos = int(std::ceil(2.0 * max_range / rho_step)) + 2;
  std::vector<double> cosines(static_cast<std::size_t>(thetas)),
      sines(static_cast<std::size_t>(thetas));
  for (int t = 0; t < thetas; ++t) {
    cosines[std::size_t(t)] = std::cos(t * angle_step);
    sines[std::size_t(t)] = std::sin(t * angle_step);
  }
  std::vector<std::uint16_t> votes(std::size_t(thetas) * std::size_t(rhos), 0);
  auto bin = [&](std::size_t k, int t) {
    const double rho = uv[k].x() * cosines[std::size_t(t)] + uv[k].y() * sines[std::size_t(t)];
    return std::size_t(t) * std::size_t(rhos) +
           std::size_t(std::lround((rho + max_range) / rho_step));
  };
  auto vote = [&](std::size_t k, int delta) {
    for (int t = 0; t < thetas; ++t)
      votes[bin(k, t)] = std::uint16_t(votes[bin(k, t)] + delta);
  };
  std::vector<bool> used(indices.size(), false);
  for (std::size_t k = 0; k < indices.size(); ++k)
    vote(k, +1);

  for (int iteration = 0; iteration < 64; ++iteration) {
    const auto peak = std::max_element(votes.begin(), votes.end());
    if (*peak < params.min_points) break;
    const std::size_t peak_index = std::size_t(peak - votes.begin());
    const int t = int(peak_index / std::size_t(rhos));
    const double rho = double(peak_index % std::size_t(rhos)) * rho_step - max_range;
    // Inliers of the peak line, then contiguous runs of them in scan order.
    std::vector<std::size_t> inliers;
    for (std::size_t k = 0; k < indices.size(); ++k) {
      if (used[k]) continue;
      const double distance =
          std::abs(uv[k].x() * cosines[std::size_t(t)] + uv[k].y() * sines[std::size_t(t)] - rho);
      if (distance <= std::max(rho_step, splitThreshold(params, at(scan, indices[k]))))
        inliers.push_back(k);
    }
    if (inliers.empty()) {
      *peak = 0;  // a bin whose points all went to earlier lines
      continue;
    }
    std::vector<std::uint32_t> run;
    auto flush = [&] {
      LineSegment segment;
      if (makeSegment(scan, line_index, run, params, segment)) found.push_back(segment);
      run.clear();
    };
    for (std::size_t n = 0; n < inliers.size(); ++n) {
      const std::size_t k = inliers[n];
      if (!run.empty()) {
        const Eigen::Vector3d p = at(scan, indices[k]);
        const double gap = (p - at(scan, run.back())).norm();
        if (gap > params.max_gap + params.gap_per_metre * p.norm() || inliers[n - 1] + 1 != k)
          flush();
      }
      run.push_back(indices[k]);
    }
    flush();
    for (std::size_t k : inliers) {
      used[k] = true;
      vote(k, -1);
    }
  }
  std::sort(found.begin(), found.end(),
            [](const LineSegment& a, const LineSegment& b) { return a.first < b.first; });
  out.insert(out.end(), found.begin(), found.end());
}

}  // namespace

std::vector<LineSegment> detectLineSegments(const Scan& scan, const LineParams& params, int threads,
                                            const ProgressCallback& progress) {
  const std::size_t lines = scan.lines.size();
  detail::PerPart<std::vector<LineSegment>> per_chunk(std::size_t(std::max(threads, 1)));
  std::atomic<bool> cancelled{false};
  std::atomic<std::size_t> done{0};
  detail::parallelChunks(lines, threads,
                         [&](std::size_t begin, std::size_t end, std::size_t chunk) {
                           for (std::size_t l = begin; l < end && !cancelled; ++l) {
                             if (params.method == LineMethod::kHough) {
                               houghLine(scan, std::uint32_t(l), params, per_chunk[chunk]);
                             } else {
                               splitAndMergeLine(scan, std::uint32_t(l), params, per_chunk[chunk]);
                             }
                             // Only the first chunk reports, so the callback is never called from
                             // two threads.
                             const std::size_t finished = ++done;
                             if (chunk == 0 && progress && finished % 64 == 0 &&
                                 !progress(double(finished) / double(lines)))
                               cancelled = true;
                           }
                         });
  if (cancelled) throw OperationCancelled();
  std::vector<LineSegment> segments;
  for (auto& chunk : per_chunk)
    segments.insert(segments.end(), chunk.begin(), chunk.end());
  return segments;
}

}  // namespace clearway
