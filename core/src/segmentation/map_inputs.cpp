// The robot-independent part of the traversability map: which cells are observed ground of which
// plane (gap-free across scan rings, never across shadows), every other point with its height
// above the local ground, and where ground planes meet.

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "clearway/segmentation/scan_analysis.h"
#include "parallel.h"

namespace clearway {
namespace {

// Half the side of the square around the scanner's foot the grid always covers: room for a robot
// of up to 2.5 m x 2.5 m on a mounting up to 1 m off its centre, plus the floor its body hides [m].
constexpr double kOwnPlaceExtent = 3.0;

constexpr double kMapMargin = 0.25;  // [m]

// Neighbouring lines are paired point by point: same index for organised scans, same relative
// position along the line for ragged ones.
std::size_t partner(const ScanLine& from, const ScanLine& to, std::size_t k) {
  if (from.count == to.count) return to.first + k;
  const std::size_t scaled = (k * to.count + from.count / 2) / std::max<std::size_t>(from.count, 1);
  return to.first + std::min(scaled, to.count - 1);
}

// Ground triangles between neighbouring scan lines whose three corners are ground of the same
// plane and close together: they cover sampling gaps but cannot bridge a shadow, because inside a
// shadow the neighbouring beam hit the obstacle, not the ground.
std::vector<std::array<std::uint32_t, 3>> groundTriangles(
    const Scan& scan, const std::vector<std::int32_t>& ground_of, double max_edge) {
  std::vector<std::array<std::uint32_t, 3>> triangles;
  const double max_edge_squared = max_edge * max_edge;
  auto close = [&](std::size_t a, std::size_t b) {
    const Point3f& p = scan.points[a];
    const Point3f& q = scan.points[b];
    const double dx = p.x - q.x, dy = p.y - q.y, dz = p.z - q.z;
    return dx * dx + dy * dy + dz * dz <= max_edge_squared;
  };
  auto add = [&](std::vector<std::array<std::uint32_t, 3>>& out, std::size_t a, std::size_t b,
                 std::size_t c) {
    const std::int32_t g = ground_of[a];
    if (g < 0 || ground_of[b] != g || ground_of[c] != g) return;
    if (!close(a, b) || !close(b, c) || !close(a, c)) return;
    out.push_back({std::uint32_t(a), std::uint32_t(b), std::uint32_t(c)});
  };
  const std::size_t lines = scan.lines.size();
  // A RoSi revolution closes on itself: its last line neighbours its first.
  const bool revolution = lines > 2 && std::isfinite(scan.lines.front().beta) && scan.isOrganised();
  const std::size_t pairs = lines == 0 ? 0 : lines - 1 + (revolution ? 1 : 0);
  std::vector<std::vector<std::array<std::uint32_t, 3>>> parts(2);
  detail::parallelChunks(pairs, 2, [&](std::size_t begin, std::size_t end, std::size_t chunk) {
    for (std::size_t l = begin; l < end; ++l) {
      const ScanLine& a = scan.lines[l];
      const ScanLine& b = scan.lines[(l + 1) % lines];
      for (std::size_t k = 0; k + 1 < a.count; ++k) {
        const std::size_t a0 = a.first + k, a1 = a0 + 1;
        const std::size_t b0 = partner(a, b, k), b1 = partner(a, b, k + 1);
        add(parts[chunk], a0, a1, b0);
        if (b1 != b0) add(parts[chunk], a1, b1, b0);
      }
    }
  });
  for (const auto& part : parts)
    triangles.insert(triangles.end(), part.begin(), part.end());
  return triangles;
}

}  // namespace

void prepareMapInputs(const Scan& scan, const SegmentationParams& params, ScanAnalysis& analysis) {
  MapInputs& inputs = analysis.inputs;
  inputs = MapInputs{};
  if (!analysis.ground_found) return;
  const Eigen::Isometry3d& map_from_scanner = analysis.map_from_scanner;
  const Eigen::Isometry3d scanner_from_map = map_from_scanner.inverse();
  const auto& point_plane = analysis.planes.point_plane;

  // Which ground candidate each point belongs to (-1: not ground).
  std::vector<std::int32_t> ground_of(scan.size(), -1);
  std::vector<bool> is_ground_plane(analysis.planes.planes.size(), false);
  for (int g : analysis.ground_planes)
    is_ground_plane[std::size_t(g)] = true;
  for (std::size_t i = 0; i < scan.size(); ++i)
    if (point_plane[i] >= 0 && is_ground_plane[std::size_t(point_plane[i])])
      ground_of[i] = point_plane[i];

  // Every point in the map frame (two halves in parallel); the grid covers the ground seen,
  // within max_extent of the scanner.
  // Floats: within max_extent (<= 500 m) they keep better than 0.1 mm, at half
  // the memory of doubles.
  std::vector<Eigen::Vector3f> mapped(scan.size());
  Eigen::AlignedBox2d halves[2];
  detail::parallelChunks(
      scan.size(), 2, [&](std::size_t begin, std::size_t end, std::size_t chunk) {
        for (std::size_t i = begin; i < end; ++i) {
          if (!scan.isValid(i)) continue;
          const Point3f& p = scan.points[i];
          mapped[i] = (map_from_scanner * Eigen::Vector3d(p.x, p.y, p.z)).cast<float>();
          if (ground_of[i] >= 0 && mapped[i].head<2>().norm() <= params.map.max_extent)
            halves[chunk].extend(mapped[i].head<2>().cast<double>());
        }
      });
  Eigen::AlignedBox2d box = halves[0];
  if (!halves[1].isEmpty()) box.extend(halves[1]);
  if (box.isEmpty()) box.extend(Eigen::Vector2d::Zero());
  // The robot stands around the scanner's foot (the map origin), where the scan often saw no
  // floor: the grid always holds its own place, whatever robot the map is computed for.
  box.extend(Eigen::Vector2d::Constant(kOwnPlaceExtent));
  box.extend(Eigen::Vector2d::Constant(-kOwnPlaceExtent));
  // Staircases too: their upper steps may be seen from below only, with no ground around them.
  for (const Staircase& staircase : analysis.stairs.staircases)
    for (const Eigen::Vector2d& corner : staircase.footprint())
      box.extend(corner);
  // A thin rim around the ground, the same for every robot so that a re-run for a new size keeps
  // the grid. Nothing outside it was observed ground, and cells outside the grid count as blocked.
  const double margin = kMapMargin;
  MapGrid& grid = inputs.grid;
  grid.resolution = params.map.resolution;
  grid.origin = (box.min().array() - margin).matrix();
  grid.width = int(std::ceil((box.max().x() - box.min().x() + 2 * margin) / grid.resolution)) + 1;
  grid.height = int(std::ceil((box.max().y() - box.min().y() + 2 * margin) / grid.resolution)) + 1;
  inputs.ground_plane.assign(grid.cells(), -1);
  inputs.ground_height.assign(grid.cells(), 0.0F);

  auto markGround = [&](int column, int row, int plane) {
    if (!grid.inside(column, row)) return;
    const std::size_t cell = grid.index(column, row);
    if (inputs.ground_plane[cell] >= 0) return;
    const Eigen::Vector2d centre = grid.centre(column, row);
    inputs.ground_plane[cell] = std::int16_t(plane);
    inputs.ground_height[cell] = float(analysis.planeHeight(plane, centre.x(), centre.y()));
  };

  // Each valid point's cell, once (two halves in parallel).
  std::vector<Eigen::Vector2i> cell_of(scan.size(), Eigen::Vector2i::Zero());
  detail::parallelChunks(scan.size(), 2, [&](std::size_t begin, std::size_t end, std::size_t) {
    for (std::size_t i = begin; i < end; ++i)
      if (scan.isValid(i)) cell_of[i] = grid.cellOf(mapped[i].x(), mapped[i].y());
  });

  // Cells holding ground points, then the cells the ground triangles cover.
  for (std::size_t i = 0; i < scan.size(); ++i)
    if (ground_of[i] >= 0) markGround(cell_of[i].x(), cell_of[i].y(), ground_of[i]);
  inputs.ground_triangles = groundTriangles(scan, ground_of, params.map.max_triangle_edge);
  // Most triangles lie within two neighbouring cells, which their corners have marked already;
  // only the larger ones are filled (two halves of the list in parallel).
  std::vector<std::vector<std::uint32_t>> large_parts(2);
  detail::parallelChunks(
      inputs.ground_triangles.size(), 2, [&](std::size_t begin, std::size_t end, std::size_t part) {
        for (std::size_t t = begin; t < end; ++t) {
          const auto& triangle = inputs.ground_triangles[t];
          const Eigen::Vector2i &a = cell_of[triangle[0]], &b = cell_of[triangle[1]],
                                &c = cell_of[triangle[2]];
          const Eigen::Vector2i span = a.cwiseMax(b).cwiseMax(c) - a.cwiseMin(b).cwiseMin(c);
          if (span.maxCoeff() > 1 || span.minCoeff() > 0)
            large_parts[part].push_back(std::uint32_t(t));
        }
      });
  std::vector<std::uint32_t> large = std::move(large_parts[0]);
  large.insert(large.end(), large_parts[1].begin(), large_parts[1].end());
  // Their cells, each thread owning half of the grid's rows (no cell is written twice).
  detail::parallelChunks(
      std::size_t(grid.height), 2, [&](std::size_t row_begin, std::size_t row_end, std::size_t) {
        for (const std::uint32_t t : large) {
          const auto& triangle = inputs.ground_triangles[t];
          const Eigen::Vector2d a = mapped[triangle[0]].head<2>().cast<double>(),
                                b = mapped[triangle[1]].head<2>().cast<double>(),
                                c = mapped[triangle[2]].head<2>().cast<double>();
          const Eigen::Vector2i low =
              cell_of[triangle[0]].cwiseMin(cell_of[triangle[1]]).cwiseMin(cell_of[triangle[2]]);
          const Eigen::Vector2i high =
              cell_of[triangle[0]].cwiseMax(cell_of[triangle[1]]).cwiseMax(cell_of[triangle[2]]);
          // Scanline fill: per row, the triangle's x-interval at the row's centre line.
          const Eigen::Vector2d corners[3] = {a, b, c};
          for (int row = std::max(low.y(), int(row_begin));
               row <= std::min(high.y(), int(row_end) - 1); ++row) {
            const double y = grid.origin.y() + (row + 0.5) * grid.resolution;
            double x_min = std::numeric_limits<double>::max(),
                   x_max = std::numeric_limits<double>::lowest();
            for (int e = 0; e < 3; ++e) {
              const Eigen::Vector2d& p = corners[e];
              const Eigen::Vector2d& q = corners[(e + 1) % 3];
              if ((p.y() - y) * (q.y() - y) > 0.0 || p.y() == q.y())
                continue;  // edge misses the line
              const double x = p.x() + (y - p.y()) * (q.x() - p.x()) / (q.y() - p.y());
              x_min = std::min(x_min, x);
              x_max = std::max(x_max, x);
            }
            if (x_min > x_max) continue;
            const int first = int(std::ceil((x_min - grid.origin.x()) / grid.resolution - 0.5));
            const int last = int(std::floor((x_max - grid.origin.x()) / grid.resolution - 0.5));
            for (int column = first; column <= last; ++column)
              markGround(column, row, ground_of[triangle[0]]);
          }
        }
      });

  // Single unobserved cells inside observed ground (a beam that fell between two cells) are
  // ground too: at least five of their eight neighbours are ground of one plane.
  std::vector<std::pair<std::size_t, int>> holes;
  for (int row = 1; row + 1 < grid.height; ++row) {
    for (int column = 1; column + 1 < grid.width; ++column) {
      if (inputs.ground_plane[grid.index(column, row)] >= 0) continue;
      // Five of eight neighbours must agree: count the neighbours' planes in a small array.
      int planes[8], counts[8], distinct = 0;
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc) {
          const int g = inputs.ground_plane[grid.index(column + dc, row + dr)];
          if (g < 0) continue;
          int k = 0;
          while (k < distinct && planes[k] != g)
            ++k;
          if (k == distinct) {
            planes[distinct] = g;
            counts[distinct++] = 0;
          }
          ++counts[k];
        }
      for (int k = 0; k < distinct; ++k)
        if (counts[k] >= 5) holes.emplace_back(grid.index(column, row), planes[k]);
    }
  }
  for (const auto& [cell, plane] : holes) {
    const int column = int(cell % std::size_t(grid.width)),
              row = int(cell / std::size_t(grid.width));
    markGround(column, row, plane);
  }

  // Every other point, with its height above the ground beneath it (two halves in parallel).
  std::vector<std::vector<MapObstacle>> found(2);
  detail::parallelChunks(
      scan.size(), 2, [&](std::size_t begin, std::size_t end, std::size_t chunk) {
        for (std::size_t i = begin; i < end; ++i) {
          if (!scan.isValid(i) || ground_of[i] >= 0) continue;
          const Eigen::Vector3d m = mapped[i].cast<double>();
          const Eigen::Vector2i& cell = cell_of[i];
          if (!grid.inside(cell.x(), cell.y())) continue;
          const std::size_t index = grid.index(cell.x(), cell.y());
          double ground = 0.0;
          if (inputs.ground_plane[index] >= 0) {
            ground = inputs.ground_height[index];
          } else {
            // Under an obstacle the ground is hidden: take the highest ground plane below the point
            // whose real area reaches there, or the reference plane.
            ground = analysis.planeHeight(analysis.reference_ground, m.x(), m.y());
            for (int g : analysis.ground_planes) {
              const double h = analysis.planeHeight(g, m.x(), m.y());
              if (h <= m.z() + 0.05 && h > ground &&
                  analysis.planes.supports[std::size_t(g)].contains(
                      scanner_from_map * Eigen::Vector3d(m.x(), m.y(), h)))
                ground = h;
            }
          }
          found[chunk].push_back({std::uint32_t(index), float(m.x()), float(m.y()), float(m.z()),
                                  float(m.z() - ground)});
        }
      });
  for (const auto& part : found)
    inputs.obstacles.insert(inputs.obstacles.end(), part.begin(), part.end());

  // Where cells of two ground planes touch, and the smallest step between them.
  std::map<std::pair<int, int>, float> steps;
  for (int row = 0; row < grid.height; ++row) {
    for (int column = 0; column < grid.width; ++column) {
      const std::size_t here = grid.index(column, row);
      const int a = inputs.ground_plane[here];
      if (a < 0) continue;
      for (const auto& [dc, dr] : {std::pair{1, 0}, std::pair{0, 1}}) {
        if (!grid.inside(column + dc, row + dr)) continue;
        const std::size_t there = grid.index(column + dc, row + dr);
        const int b = inputs.ground_plane[there];
        if (b < 0 || b == a) continue;
        const float step = std::abs(inputs.ground_height[here] - inputs.ground_height[there]);
        const auto key = std::minmax(a, b);
        const auto it = steps.find(key);
        if (it == steps.end() || step < it->second) steps[key] = step;
      }
    }
  }
  for (const auto& [key, step] : steps)
    inputs.contacts.push_back({key.first, key.second, step});
}

}  // namespace clearway
