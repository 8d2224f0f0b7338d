// Stage 3: a plane is real only if its supporting points cover a connected area of some size on
// the plane (paper II-C). Phantom planes that cut through real ones collect support only along
// thin intersection lines, which the morphological opening removes before the area is measured.

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "clearway/segmentation/planes.h"
#include "parallel.h"
#include "ring_support.h"
#include "row_dilation.h"

namespace clearway {
namespace {

// Planes whose real area is this many times the minimum extend over their sparse outer rings.
constexpr int kGrowthAreaFactor = 5;

// Consecutive points of a scan line lie close together: a plane that passes far from a block's
// bounding box has no support in it, and the block is skipped without looking at its points.
constexpr std::size_t kBlock = 32;

struct PointBlock {
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  Eigen::Vector3f half_size = Eigen::Vector3f::Constant(-1.0F);  // negative: no valid point
};

std::vector<PointBlock> pointBlocks(const Scan& scan, int threads) {
  std::vector<PointBlock> blocks((scan.size() + kBlock - 1) / kBlock);
  detail::parallelChunks(
      blocks.size(), threads, [&](std::size_t begin, std::size_t end, std::size_t) {
        for (std::size_t b = begin; b < end; ++b) {
          Eigen::AlignedBox3f box;
          for (std::size_t i = b * kBlock; i < std::min(scan.size(), (b + 1) * kBlock); ++i)
            if (scan.isValid(i))
              box.extend(Eigen::Vector3f(scan.points[i].x, scan.points[i].y, scan.points[i].z));
          if (!box.isEmpty()) blocks[b] = {box.center(), box.sizes() / 2};
        }
      });
  return blocks;
}

// Supporting point indices of a plane; `inner` counts those within half the distance.
std::vector<std::uint32_t> supportingPoints(const Scan& scan, const std::vector<PointBlock>& blocks,
                                            const Plane& plane, double distance, double per_metre,
                                            std::size_t& inner) {
  const Eigen::Vector3f normal = plane.normal.cast<float>();
  const Eigen::Vector3f reach = normal.cwiseAbs();
  const float offset = float(plane.offset), tolerance = float(distance), half = tolerance / 2;
  std::vector<std::uint32_t> support;
  inner = 0;
  float distances[kBlock];
  const Point3f* points = scan.points.data();
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const PointBlock& block = blocks[b];
    if (block.half_size.x() < 0.0F) continue;
    // The box's points are within reach . half_size of its centre's distance to the plane.
    // The band at the block's farthest range.
    const float block_tolerance =
        tolerance + float(per_metre) * (block.centre.norm() + block.half_size.norm());
    const float slack = block_tolerance + reach.dot(block.half_size) + 1e-4F;
    if (std::abs(normal.dot(block.centre) - offset) > slack) continue;
    const std::size_t first = b * kBlock, count = std::min(kBlock, scan.size() - first);
    // The distances first, in a loop the compiler vectorises, then the few hits.
    for (std::size_t j = 0; j < count; ++j) {
      const Point3f& p = points[first + j];
      distances[j] = std::abs(normal.x() * p.x + normal.y() * p.y + normal.z() * p.z - offset);
    }
    for (std::size_t j = 0; j < count; ++j) {
      if (!(distances[j] <= block_tolerance) || !scan.isValid(first + j)) continue;
      float band = tolerance, half_band = half;
      if (per_metre > 0.0) {
        const Point3f& p = points[first + j];
        band += float(per_metre) * std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
        half_band = band / 2;
        if (distances[j] > band) continue;
      }
      support.push_back(std::uint32_t(first + j));
      inner += distances[j] <= half_band;
    }
  }
  return support;
}

// The crowding of a plane's support about the local surface: each point's distance to the plane
// less the mean distance of its support cell's points, against the inner half of its band. Only
// cells with at least min_cell_points points count (a lone point has no spread to judge). A real
// surface that bends away from the plane (a road's camber, a kerb's level) stays crowded; a phantom
// cutting real surfaces at an angle spreads over the band within every cell.
template <typename CellOf>
double crowdingAboutCells(const Scan& scan, const Plane& plane,
                          const std::vector<std::uint32_t>& support,
                          const std::vector<Eigen::Vector2d>& uv, const CellOf& cellOf,
                          const cv::Mat& counts, const ValidationParams& params, double per_metre) {
  std::vector<float> sum(std::size_t(counts.rows) * std::size_t(counts.cols), 0.0F);
  std::vector<float> distance(support.size());
  std::vector<int> cell_of(support.size());
  for (std::size_t k = 0; k < support.size(); ++k) {
    const Point3f& p = scan.points[support[k]];
    distance[k] = float(plane.signedDistance(Eigen::Vector3d(p.x, p.y, p.z)));
    cell_of[k] = cellOf(uv[k]);
    if (cell_of[k] >= 0) sum[std::size_t(cell_of[k])] += distance[k];
  }
  std::size_t judged = 0, inner = 0;
  for (std::size_t k = 0; k < support.size(); ++k) {
    const int cell = cell_of[k];
    if (cell < 0) continue;
    const int count = counts.ptr<std::uint16_t>()[cell];
    if (count < params.min_cell_points) continue;
    const Point3f& p = scan.points[support[k]];
    const double range = std::sqrt(double(p.x) * p.x + double(p.y) * p.y + double(p.z) * p.z);
    const double half_band = (params.support_distance + per_metre * range) / 2;
    ++judged;
    inner += std::abs(distance[k] - sum[std::size_t(cell)] / float(count)) <= half_band;
  }
  return judged == 0 ? 0.0 : double(inner) / double(judged);
}

// Returns the area of its largest connected supported area; with `local_inner_fraction`, also the
// share of support within the inner half of the band about its own cell's mean distance; with
// `segments`, the plane's area is kept near its own segments; with `rings` (a multi-beam frame),
// cells between neighbouring rings that both support the plane are supported (ring_support.h).
double buildSupportImage(const Scan& scan, const Plane& plane,
                         const std::vector<std::uint32_t>& support, const ValidationParams& params,
                         double growth_gap, double per_metre, SupportImage& image,
                         double* local_inner_fraction, const std::vector<LineSegment>* segments,
                         const detail::RingLayout& rings) {
  image.u_axis = plane.normal.unitOrthogonal();
  image.v_axis = plane.normal.cross(image.u_axis);
  image.cell = params.cell_size;
  // The image covers the plane's own points' surroundings, clipped to a sane size.
  const Eigen::Vector3d centre = plane.moments.mean();
  double u_min = 1e300, u_max = -1e300, v_min = 1e300, v_max = -1e300;
  std::vector<Eigen::Vector2d> uv;
  uv.reserve(support.size());
  for (std::uint32_t i : support) {
    const Point3f& p = scan.points[i];
    const Eigen::Vector3d q = Eigen::Vector3d(p.x, p.y, p.z) - centre;
    uv.emplace_back(q.dot(image.u_axis), q.dot(image.v_axis));
    u_min = std::min(u_min, uv.back().x());
    u_max = std::max(u_max, uv.back().x());
    v_min = std::min(v_min, uv.back().y());
    v_max = std::max(v_max, uv.back().y());
  }
  const double max_side = std::sqrt(double(params.max_image_cells)) * params.cell_size / 2.0;
  // Kept near its own segments, the plane's image needs to cover only them and the growth gap
  // around them (a wall's band crosses the whole frame; its own rings span a few metres).
  std::vector<Eigen::Vector2d> own_uv;
  if (segments) {
    double own_u_min = 1e300, own_u_max = -1e300, own_v_min = 1e300, own_v_max = -1e300;
    for (const std::uint32_t s : plane.segments) {
      const LineSegment& segment = (*segments)[s];
      for (std::size_t i = segment.first; i <= segment.last; ++i) {
        if (!scan.isValid(i)) continue;
        const Point3f& p = scan.points[i];
        const Eigen::Vector3d q = Eigen::Vector3d(p.x, p.y, p.z) - centre;
        own_uv.emplace_back(q.dot(image.u_axis), q.dot(image.v_axis));
        own_u_min = std::min(own_u_min, own_uv.back().x());
        own_u_max = std::max(own_u_max, own_uv.back().x());
        own_v_min = std::min(own_v_min, own_uv.back().y());
        own_v_max = std::max(own_v_max, own_uv.back().y());
      }
    }
    u_min = std::max(u_min, own_u_min - growth_gap);
    v_min = std::max(v_min, own_v_min - growth_gap);
    u_max = std::min(u_max, own_u_max + growth_gap);
    v_max = std::min(v_max, own_v_max + growth_gap);
    if (u_min > u_max || v_min > v_max) {  // no support near its own segments
      u_max = u_min;
      v_max = v_min;
    }
  }
  u_min = std::max(u_min, -max_side);
  v_min = std::max(v_min, -max_side);
  u_max = std::min(u_max, max_side);
  v_max = std::min(v_max, max_side);
  image.u0 = u_min + centre.dot(image.u_axis);
  image.v0 = v_min + centre.dot(image.v_axis);
  image.width = std::max(1, int(std::ceil((u_max - u_min) / params.cell_size)) + 1);
  image.height = std::max(1, int(std::ceil((v_max - v_min) / params.cell_size)) + 1);

  // Freshly allocated images are continuous: a cell's index (cellOf) addresses them directly.
  cv::Mat counts(image.height, image.width, CV_16UC1, cv::Scalar(0));
  auto cellOf = [&](const Eigen::Vector2d& q) -> int {
    const int column = int((q.x() - u_min) / params.cell_size);
    const int row = int((q.y() - v_min) / params.cell_size);
    if (column < 0 || row < 0 || column >= image.width || row >= image.height) return -1;
    return row * image.width + column;
  };
  for (const Eigen::Vector2d& q : uv) {
    const int cell = cellOf(q);
    if (cell < 0) continue;
    auto& count = counts.ptr<std::uint16_t>()[cell];
    if (count < 65535) ++count;
  }
  if (local_inner_fraction)
    *local_inner_fraction =
        crowdingAboutCells(scan, plane, support, uv, cellOf, counts, params, per_metre);
  // Validation: the dense, connected part of the support, with thin strips (where a phantom
  // plane cuts real ones) opened away.
  const double cell_area = params.cell_size * params.cell_size;
  const int min_cells = std::max(1, int(std::ceil(params.min_area / cell_area)));
  cv::Mat supported, labels, stats, centroids;
  int largest = 0;
  std::vector<std::uint8_t> real;
  auto measure = [&] {
    supported = counts >= params.min_cell_points;  // CV_8U, 255 where supported
    cv::morphologyEx(supported, supported, cv::MORPH_OPEN,
                     cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
    const int components =
        cv::connectedComponentsWithStats(supported, labels, stats, centroids, 8, CV_32S);
    largest = 0;
    real.assign(std::size_t(components), 0);
    for (int c = 1; c < components; ++c) {
      const int area = stats.at<int>(c, cv::CC_STAT_AREA);
      largest = std::max(largest, area);
      real[std::size_t(c)] = area >= min_cells;
    }
  };
  measure();
  // A plane whose own returns are not enough to grow may be a surface seen by sparse rings, each
  // a thin arc the opening took away: measured again with the cells between facing rings
  // supported (ring_support.h). A plane that grows already spans its rings' gaps (below).
  if (!rings.empty() && largest < kGrowthAreaFactor * min_cells) {
    detail::supportBetweenRings(
        scan, rings, params.cell_size, growth_gap, plane, params.support_distance, per_metre,
        support, uv, {centre, image.u_axis, image.v_axis, {u_min, v_min}, params.cell_size}, counts,
        params.min_cell_points);
    measure();
  }

  // Membership: for large planes, every supported cell reachable from a real area across gaps of
  // up to two cells, so the sparse outer scan rings of a floor still belong to it. Small planes (a
  // pallet top) do not grow: the foot of every wall crosses their height, and growing along it
  // would give them points far away.
  const bool grows = largest >= kGrowthAreaFactor * min_cells;
  cv::Mat reach = grows ? cv::Mat(counts > 0) : cv::Mat(supported.clone());
  const int gap_cells = std::max(1, int(std::lround(growth_gap / params.cell_size)));
  const cv::Mat gap_disk =
      cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * gap_cells + 1, 2 * gap_cells + 1));
  if (grows) detail::dilateByCentredRows(reach, reach, gap_disk);
  cv::Mat reach_labels;
  const int reach_components = cv::connectedComponents(reach, reach_labels, 8, CV_32S);
  // Row by row through pointers: a multi-beam frame's road image has hundreds of thousands of
  // cells, and these loops ran for every one of them.
  std::vector<std::uint8_t> keep(std::size_t(reach_components), 0);
  for (int row = 0; row < image.height; ++row) {
    const int* component = labels.ptr<int>(row);
    const int* reached = reach_labels.ptr<int>(row);
    for (int column = 0; column < image.width; ++column)
      if (real[std::size_t(component[column])]) keep[std::size_t(reached[column])] = 1;
  }
  image.kept.assign(std::size_t(image.width) * std::size_t(image.height), 0);
  for (int row = 0; row < image.height; ++row) {
    const std::uint16_t* count = counts.ptr<std::uint16_t>(row);
    const std::uint8_t* dense = supported.ptr<std::uint8_t>(row);
    const int* reached = reach_labels.ptr<int>(row);
    std::uint8_t* kept = image.kept.data() + std::size_t(row) * std::size_t(image.width);
    for (int column = 0; column < image.width; ++column)
      kept[column] =
          (grows ? count[column] > 0 : dense[column] > 0) && keep[std::size_t(reached[column])];
  }
  if (segments) {
    // The plane is known only near the points it was fitted to: its area stays within the growth
    // gap of its own segments.
    cv::Mat own(image.height, image.width, CV_8UC1, cv::Scalar(0));
    for (const Eigen::Vector2d& q : own_uv) {
      const int cell = cellOf(q);
      if (cell >= 0) own.ptr<std::uint8_t>()[cell] = 255;
    }
    detail::dilateByCentredRows(own, own, gap_disk);
    for (int row = 0; row < image.height; ++row) {
      const std::uint8_t* near_own = own.ptr<std::uint8_t>(row);
      std::uint8_t* kept = image.kept.data() + std::size_t(row) * std::size_t(image.width);
      for (int column = 0; column < image.width; ++column)
        kept[column] = near_own[column] ? kept[column] : 0;
    }
  }
  return largest * cell_area;
}

}  // namespace

bool SupportImage::contains(const Eigen::Vector3d& p) const {
  const int column = int(std::floor((p.dot(u_axis) - u0) / cell));
  const int row = int(std::floor((p.dot(v_axis) - v0) / cell));
  if (column < 0 || row < 0 || column >= width || row >= height) return false;
  return kept[std::size_t(row) * std::size_t(width) + std::size_t(column)] != 0;
}

// Candidates differ in size by orders of magnitude (the floor against a pallet's side): each is a
// task of its own, taken by whichever thread is free.
constexpr std::size_t kCandidatesPerThread = 64;

ValidatedPlanes validatePlanes(const Scan& scan, std::vector<Plane> candidates,
                               const ValidationParams& params, int threads,
                               const SensorSpread& spread) {
  std::vector<SupportImage> images(candidates.size());
  std::vector<std::vector<std::uint32_t>> supports(candidates.size());
  const std::vector<PointBlock> blocks = pointBlocks(scan, threads);
  // The frame's ring layout: the caller's when it worked it out (it serves later stages too).
  detail::RingLayout own_layout;
  if (!spread.ring_layout)
    own_layout =
        detail::ringLayout(scan, spread.rings_by_elevation, spread.ring_azimuth_step, threads);
  const detail::RingLayout& rings = spread.ring_layout ? *spread.ring_layout : own_layout;
  detail::parallelChunks(
      candidates.size(), threads,
      [&](std::size_t begin, std::size_t end, std::size_t) {
        for (std::size_t k = begin; k < end; ++k) {
          Plane& plane = candidates[k];
          std::size_t inner = 0;
          supports[k] = supportingPoints(scan, blocks, plane, params.support_distance,
                                         spread.support_per_metre, inner);
          plane.support_points = supports[k].size();
          double local_inner = 0.0;
          const double area =
              supports[k].empty()
                  ? 0.0
                  : buildSupportImage(scan, plane, supports[k], params, spread.growth_gap,
                                      spread.support_per_metre, images[k],
                                      spread.local_crowding ? &local_inner : nullptr,
                                      spread.own_segments, rings);
          plane.support_area = area;
          plane.inner_fraction = supports[k].empty() ? 0.0
                                 : spread.local_crowding
                                     ? local_inner
                                     : double(inner) / double(supports[k].size());
          plane.validated =
              area >= params.min_area && plane.inner_fraction >= params.min_inner_fraction;
        }
      },
      kCandidatesPerThread);

  ValidatedPlanes result;
  result.point_plane.assign(scan.size(), -1);
  std::vector<float> best_distance(scan.size(), std::numeric_limits<float>::max());
  result.min_area = params.min_area;
  result.min_inner_fraction = params.min_inner_fraction;
  std::vector<std::size_t> validated;  // candidate of each validated plane, in order
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    if (candidates[k].validated) {
      validated.push_back(k);
      continue;
    }
    ++result.rejected;
    const Plane& plane = candidates[k];
    result.rejected_planes.push_back({plane.normal, plane.offset, plane.support_points,
                                      plane.support_area, plane.inner_fraction});
  }
  // A point belongs to the nearest validated plane that supports it within that plane's area
  // (the first of equally near ones). Points are independent: each thread takes a range of them,
  // and from each plane's support (sorted by point) the part in its range.
  detail::parallelChunks(
      scan.size(), threads, [&](std::size_t first, std::size_t end, std::size_t) {
        for (std::size_t n = 0; n < validated.size(); ++n) {
          const std::size_t k = validated[n];
          const Plane& plane = candidates[k];
          const SupportImage& image = images[k];
          const std::vector<std::uint32_t>& support = supports[k];
          auto it = std::lower_bound(support.begin(), support.end(), std::uint32_t(first));
          for (; it != support.end() && *it < end; ++it) {
            const std::uint32_t i = *it;
            const Point3f& p = scan.points[i];
            const Eigen::Vector3d q(p.x, p.y, p.z);
            const float distance = float(std::abs(plane.signedDistance(q)));
            if (distance < best_distance[i] && image.contains(q)) {
              best_distance[i] = distance;
              result.point_plane[i] = std::int32_t(n);
            }
          }
        }
      });
  for (const std::size_t k : validated) {
    result.planes.push_back(std::move(candidates[k]));
    result.supports.push_back(std::move(images[k]));
  }
  return result;
}

}  // namespace clearway
