// The robot-independent part of the traversability map: which cells are observed ground of which
// plane (gap-free across scan rings, never across shadows), every other point with its height
// above the local ground, and where ground planes meet.

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <optional>

#include "clearway/segmentation/scan_analysis.h"
#include "parallel.h"

namespace clearway {
namespace {

// Half the side of the square around the scanner's foot the grid always covers: room for a robot
// of up to 2.5 m x 2.5 m on a mounting up to 1 m off its centre, plus the floor its body hides [m].
constexpr double kOwnPlaceExtent = 3.0;

constexpr double kMapMargin = 0.25;  // [m]

constexpr double kPi = std::numbers::pi;
// A full turn closes over a gap between neighbouring lines of at most this many line steps, or
// kLargestSeamGap (lines lost at the start and end of the turn); the density check keeps such a
// wedge from showing green.
constexpr double kSeamSteps = 2.5;
constexpr double kLargestSeamGap = 15.0 * kPi / 180.0;

// Neighbouring lines are paired point by point: same index for organised scans, same relative
// position along the line for ragged ones.
std::size_t partner(const ScanLine& from, const ScanLine& to, std::size_t k) {
  if (from.count == to.count) return to.first + k;
  const std::size_t scaled = (k * to.count + from.count / 2) / std::max<std::size_t>(from.count, 1);
  return to.first + std::min(scaled, to.count - 1);
}

// The angle that runs along each line, per point: elevation along a rotating scanner's fans,
// azimuth (unwrapped) along a multi-beam ring. Points without a direction take their
// predecessor's, so the values stay ordered along the line.
std::vector<double> angleAlongLines(const Scan& scan, bool multi_beam) {
  std::vector<double> along(scan.size(), 0.0);
  for (const ScanLine& line : scan.lines) {
    double previous = 0.0, raw_previous = 0.0;
    bool started = false;
    for (std::size_t i = line.first; i < line.first + line.count; ++i) {
      const Point3f& p = scan.points[i];
      const double horizontal = std::hypot(double(p.x), double(p.y));
      if (!scan.isValid(i) || horizontal + std::abs(p.z) <= 1e-6) {
        along[i] = previous;
        continue;
      }
      if (!multi_beam) {
        previous = std::atan2(double(p.z), horizontal);
      } else {
        const double raw = std::atan2(double(p.y), double(p.x));
        previous =
            started ? previous + std::remainder(raw - raw_previous, 2.0 * std::numbers::pi) : raw;
        raw_previous = raw;
      }
      started = true;
      along[i] = previous;
    }
  }
  return along;
}

// For each point of line a, the point of line b nearest in the angle along the line (both run the
// same way, so one walk over b serves the whole of a).
void partnersByAngle(const std::vector<double>& along, const ScanLine& a, const ScanLine& b,
                     std::vector<std::size_t>& partners) {
  partners.resize(a.count);
  std::size_t j = b.first;
  const std::size_t b_end = b.first + b.count;
  for (std::size_t k = 0; k < a.count; ++k) {
    const double target = along[a.first + k];
    while (j + 1 < b_end && std::abs(along[j + 1] - target) <= std::abs(along[j] - target))
      ++j;
    partners[k] = j;
  }
}

// The lines in the order they lie side by side, and whether the last lies next to the first.
// A rotating scanner's lines go by their turntable angle, not by the file: a 2D field wider than
// half a turn writes a fan's two halves 180 deg apart one after the other, and a turntable that
// overran writes its first lines' neighbours at the end. Sorted by angle, the order starts after
// the widest gap between neighbours; it closes over that gap when the gap is no wider than a
// missing line or two (a full turn: the seam). Multi-beam rings and unknown sensors keep the file
// order and never close.
struct LineOrder {
  std::vector<std::size_t> lines;
  bool closes = false;
};

LineOrder linesSideBySide(const Scan& scan, const SensorGeometry& sensor) {
  LineOrder order;
  const std::size_t count = scan.lines.size();
  if (sensor.line_angle.size() != count || sensor.kind != SensorKind::kRotating2D) {
    for (std::size_t l = 0; l < count; ++l)
      order.lines.push_back(l);
    return order;
  }
  for (std::size_t l = 0; l < count; ++l)
    if (std::isfinite(sensor.line_angle[l])) order.lines.push_back(l);
  if (order.lines.size() < 3) return order;
  auto angle = [&](std::size_t l) { return std::remainder(sensor.line_angle[l], 2.0 * kPi); };
  std::stable_sort(order.lines.begin(), order.lines.end(),
                   [&](std::size_t a, std::size_t b) { return angle(a) < angle(b); });
  std::size_t widest = order.lines.size() - 1;  // the gap after this position (wrap: last)
  double widest_gap = angle(order.lines.front()) + 2.0 * kPi - angle(order.lines.back());
  for (std::size_t k = 0; k + 1 < order.lines.size(); ++k) {
    const double gap = angle(order.lines[k + 1]) - angle(order.lines[k]);
    if (gap > widest_gap) {
      widest_gap = gap;
      widest = k;
    }
  }
  std::rotate(order.lines.begin(), order.lines.begin() + std::ptrdiff_t(widest + 1),
              order.lines.end());
  order.closes = widest_gap <= std::max(kSeamSteps * sensor.between_line_step, kLargestSeamGap);
  return order;
}

// Ground triangles between neighbouring scan lines whose three corners are ground of the same
// plane and close together: they cover sampling gaps but cannot bridge a shadow, because inside a
// shadow the neighbouring beam hit the obstacle, not the ground.
// The longest triangle edge allowed near a point: the fixed limit, or where the scan is sparser
// (far ground), a few times the spacing the sensor's angular steps give at that range. Whether an
// obstacle could hide in such a triangle is the density check's question (cell_classes.cpp).
struct EdgeLimit {
  const std::vector<Eigen::Vector3f>& mapped;
  const SensorGeometry& sensor;
  double fixed = 1.0;
  double scanner_height = 1.0;
  double maxEdgeSquared(std::size_t point) const {
    const double range = double(mapped[point].head<2>().norm());
    const double spacing = expectedGroundSpacing(sensor, range, scanner_height);
    const double edge = std::max(fixed, kSpacingsPerEdge * std::min(spacing, kLongestEdge));
    return edge * edge;
  }
  // Two samples' worth of slack: a beam lost between neighbours still closes the triangle.
  static constexpr double kSpacingsPerEdge = 2.0;
  // However sparse the scan, no triangle edge is longer than this [m].
  static constexpr double kLongestEdge = 5.0;
};

// Triangles whose corners lie on different ground planes join them only if the corners' heights
// differ by at most this much [m] (half the smallest step a robot is told about).
constexpr float kLargestSeamStep = 0.05F;

// Elevation angles tell the beams of a fan apart on the ground only from this high above it [m].
constexpr double kElevationHeight = 0.5;

// A scanner "at ground level" (files whose origin is on the floor) still sees the ground at a
// grazing angle; its spacing is worked out for at least this height [m].
constexpr double kLowestScannerHeight = 0.3;

std::vector<std::array<std::uint32_t, 3>> groundTriangles(
    const Scan& scan, const std::vector<std::int32_t>& ground_of, const EdgeLimit& limit,
    const SensorGeometry& sensor, double scanner_height) {
  std::vector<std::array<std::uint32_t, 3>> triangles;
  auto close = [&](std::size_t a, std::size_t b, double max_edge_squared) {
    const Point3f& p = scan.points[a];
    const Point3f& q = scan.points[b];
    const double dx = p.x - q.x, dy = p.y - q.y, dz = p.z - q.z;
    return dx * dx + dy * dy + dz * dz <= max_edge_squared;
  };
  auto add = [&](std::vector<std::array<std::uint32_t, 3>>& out, std::size_t a, std::size_t b,
                 std::size_t c) {
    const std::int32_t g = ground_of[a];
    if (g < 0 || ground_of[b] < 0 || ground_of[c] < 0) return;
    // Ground of two planes joins only where the two meet without a step: the outdoor ground is
    // several planes that touch (a paving's slight bends), a stair's treads are not.
    if (ground_of[b] != g || ground_of[c] != g) {
      const float za = limit.mapped[a].z(), zb = limit.mapped[b].z(), zc = limit.mapped[c].z();
      if (std::max({za, zb, zc}) - std::min({za, zb, zc}) > kLargestSeamStep) return;
    }
    const double max_edge_squared = limit.maxEdgeSquared(a);
    if (!close(a, b, max_edge_squared) || !close(b, c, max_edge_squared) ||
        !close(a, c, max_edge_squared))
      return;
    out.push_back({std::uint32_t(a), std::uint32_t(b), std::uint32_t(c)});
  };
  // Lines side by side: in the order of their angle (file order when the sensor's geometry is
  // unknown); a full turn closes on itself, its last line next to its first.
  const LineOrder side_by_side = linesSideBySide(scan, sensor);
  const std::vector<std::size_t>& order = side_by_side.lines;
  const std::size_t lines = order.size();
  const bool revolution = lines > 2 && side_by_side.closes;
  const std::size_t pairs = lines == 0 ? 0 : lines - 1 + (revolution ? 1 : 0);
  // Ragged lines (sky and no-returns dropped, rings of different lengths) are paired by the angle
  // along the line, not by index: the azimuth along a ring; the elevation along a fan, where it
  // tells the beams apart, which it does not when the file's origin lies on the ground (every
  // ground point then has an elevation near zero): those keep the pairing by relative index.
  const bool multi_beam = sensor.kind == SensorKind::kMultiBeam;
  const bool by_angle = !scan.isOrganised() && (multi_beam || scanner_height >= kElevationHeight);
  const std::vector<double> along =
      by_angle ? angleAlongLines(scan, multi_beam) : std::vector<double>{};
  std::vector<std::vector<std::array<std::uint32_t, 3>>> parts(2);
  detail::parallelChunks(pairs, 2, [&](std::size_t begin, std::size_t end, std::size_t chunk) {
    std::vector<std::size_t> partners;
    for (std::size_t l = begin; l < end; ++l) {
      const ScanLine& a = scan.lines[order[l]];
      const ScanLine& b = scan.lines[order[(l + 1) % lines]];
      if (a.count == 0 || b.count == 0) continue;
      if (!along.empty()) partnersByAngle(along, a, b, partners);
      auto partnerOf = [&](std::size_t k) {
        return along.empty() ? partner(a, b, k) : partners[k];
      };
      for (std::size_t k = 0; k + 1 < a.count; ++k) {
        const std::size_t a0 = a.first + k, a1 = a0 + 1;
        const std::size_t b0 = partnerOf(k), b1 = partnerOf(k + 1);
        add(parts[chunk], a0, a1, b0);
        if (b1 != b0) add(parts[chunk], a1, b1, b0);
      }
    }
  });
  for (const auto& part : parts)
    triangles.insert(triangles.end(), part.begin(), part.end());
  return triangles;
}

// The local ground beside a cell that has none (a wall's foot, a trunk): the lowest ground cell
// within kLocalGroundReach, if any (lowest: an obstacle is never measured as lower than it is).
std::optional<double> groundAround(const MapInputs& inputs, const Eigen::Vector2i& cell) {
  constexpr int kLocalGroundReach = 3;  // cells (0.15 m at the default resolution)
  double lowest = std::numeric_limits<double>::max();
  bool any = false;
  for (int dr = -kLocalGroundReach; dr <= kLocalGroundReach; ++dr)
    for (int dc = -kLocalGroundReach; dc <= kLocalGroundReach; ++dc) {
      if (!inputs.grid.inside(cell.x() + dc, cell.y() + dr)) continue;
      const std::size_t next = inputs.grid.index(cell.x() + dc, cell.y() + dr);
      if (inputs.ground_plane[next] < 0) continue;
      lowest = std::min(lowest, double(inputs.ground_height[next]));
      any = true;
    }
  if (!any) return std::nullopt;
  return lowest;
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

  // A ground cell's height is the local ground's: its own points' mean, or the triangle over it,
  // not its plane's (an outdoor plane is only an approximation of the road far from its centre).
  auto markGround = [&](int column, int row, int plane, float height) {
    if (!grid.inside(column, row)) return;
    const std::size_t cell = grid.index(column, row);
    if (inputs.ground_plane[cell] >= 0) return;
    inputs.ground_plane[cell] = std::int16_t(plane);
    inputs.ground_height[cell] = height;
  };

  // Each valid point's cell, once (two halves in parallel).
  std::vector<Eigen::Vector2i> cell_of(scan.size(), Eigen::Vector2i::Zero());
  detail::parallelChunks(scan.size(), 2, [&](std::size_t begin, std::size_t end, std::size_t) {
    for (std::size_t i = begin; i < end; ++i)
      if (scan.isValid(i)) cell_of[i] = grid.cellOf(mapped[i].x(), mapped[i].y());
  });

  // Cells holding ground points, then the cells the ground triangles cover.
  {
    // The lowest of the cell's ground points: the support band also takes in the foot of a low
    // obstacle, which must not raise the ground it is measured against.
    std::vector<float> lowest(grid.cells(), std::numeric_limits<float>::max());
    for (std::size_t i = 0; i < scan.size(); ++i) {
      if (ground_of[i] < 0) continue;
      markGround(cell_of[i].x(), cell_of[i].y(), ground_of[i], 0.0F);
      if (!grid.inside(cell_of[i].x(), cell_of[i].y())) continue;
      const std::size_t cell = grid.index(cell_of[i].x(), cell_of[i].y());
      if (inputs.ground_plane[cell] != ground_of[i]) continue;
      lowest[cell] = std::min(lowest[cell], mapped[i].z());
    }
    for (std::size_t cell = 0; cell < grid.cells(); ++cell)
      if (lowest[cell] < std::numeric_limits<float>::max())
        inputs.ground_height[cell] = lowest[cell];
  }
  const EdgeLimit limit{mapped, analysis.sensor, params.map.max_triangle_edge,
                        std::max(kLowestScannerHeight, map_from_scanner.translation().z())};
  inputs.ground_triangles =
      groundTriangles(scan, ground_of, limit, analysis.sensor, map_from_scanner.translation().z());
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
          // The triangle's height over the map: z = h0 + hx x + hy y through its corners, from
          // its normal (closed form: a QR solve per triangle was a tenth of a multi-beam frame's
          // time). A triangle flat in x-y covers no cell centre; it keeps its first corner's z.
          const Eigen::Vector3d p0 = mapped[triangle[0]].cast<double>();
          const Eigen::Vector3d normal = (mapped[triangle[1]].cast<double>() - p0)
                                             .cross(mapped[triangle[2]].cast<double>() - p0);
          Eigen::Vector3d h(p0.z(), 0.0, 0.0);
          if (std::abs(normal.z()) > 1e-12) {
            h[1] = -normal.x() / normal.z();
            h[2] = -normal.y() / normal.z();
            h[0] = p0.z() - h[1] * p0.x() - h[2] * p0.y();
          }
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
            for (int column = first; column <= last; ++column) {
              const Eigen::Vector2d centre = grid.centre(column, row);
              markGround(column, row, ground_of[triangle[0]],
                         float(h[0] + h[1] * centre.x() + h[2] * centre.y()));
            }
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
    // A hole is as high as the ground of its plane around it.
    float height = 0.0F;
    int neighbours = 0;
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc) {
        const std::size_t next = grid.index(column + dc, row + dr);
        if (inputs.ground_plane[next] != plane || next == cell) continue;
        height += inputs.ground_height[next];
        ++neighbours;
      }
    markGround(column, row, plane, height / float(std::max(neighbours, 1)));
  }

  // What could hide between the ground samples of each ground cell (docs/ALGORITHM.md).
  inputs.ground_spacing.assign(grid.cells(), std::numeric_limits<float>::infinity());
  for (int row = 0; row < grid.height; ++row)
    for (int column = 0; column < grid.width; ++column) {
      const std::size_t cell = grid.index(column, row);
      if (inputs.ground_plane[cell] < 0) continue;
      const Eigen::Vector2d centre = grid.centre(column, row);
      const Eigen::Vector3d ground(centre.x(), centre.y(), inputs.ground_height[cell]);
      inputs.ground_spacing[cell] = float(
          hiddenObstacleSize(analysis.sensor, scanner_from_map * ground, analysis.up,
                             map_from_scanner.translation().z() - inputs.ground_height[cell]));
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
          } else if (const auto local = groundAround(inputs, cell)) {
            ground = *local;
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
