// The robot-independent part of the traversability map: which cells are observed ground of which
// plane (gap-free across scan rings, never across shadows), every other point with its height
// above the local ground, and where ground planes meet.

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "clearway/segmentation/scan_analysis.h"
#include "face_returns.h"
#include "floor_crossings.h"
#include "ground_continuation.h"
#include "ground_triangles.h"
#include "parallel.h"
#include "plane_borders.h"
#include "release_memory.h"
#include "view_limit.h"

namespace clearway {
namespace {

// Half the side of the square around the scanner's foot the grid always covers: room for a robot
// of up to 2.5 m x 2.5 m on a mounting up to 1 m off its centre, plus the floor its body hides [m].
constexpr double kOwnPlaceExtent = 3.0;

constexpr double kMapMargin = 0.25;  // [m]

// The local ground beside a cell that has none (a wall's foot, a trunk): the lowest ground cell
// within kLocalGroundReach, if any (lowest: an obstacle is never measured as lower than it is).
// For every cell at once (a minimum filter over the ground heights, no ground counting as
// +infinity): a wall's cells hold many points each, and asking per point read 49 cells per point.
std::vector<float> lowestGroundAround(const MapInputs& inputs) {
  constexpr int kLocalGroundReach = 3;  // cells (0.15 m at the default resolution)
  constexpr float kNoGround = std::numeric_limits<float>::infinity();
  const MapGrid& grid = inputs.grid;
  std::vector<float> heights(grid.cells(), kNoGround);
  for (std::size_t cell = 0; cell < grid.cells(); ++cell)
    if (inputs.ground_plane[cell] >= 0) heights[cell] = inputs.ground_height[cell];
  std::vector<float> lowest(grid.cells(), kNoGround);
  if (grid.cells() == 0) return lowest;
  // Rows of the grid are rows of the image (cells are stored row by row).
  const cv::Mat source(grid.height, grid.width, CV_32FC1, heights.data());
  cv::Mat result(grid.height, grid.width, CV_32FC1, lowest.data());
  const int side = 2 * kLocalGroundReach + 1;
  cv::erode(source, result, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(side, side)),
            cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(kNoGround));
  return lowest;
}

// Which ground candidate each point belongs to (-1: not ground).
std::vector<std::int32_t> groundOfPoints(const Scan& scan, const ScanAnalysis& analysis) {
  const auto& point_plane = analysis.planes.point_plane;
  std::vector<std::int32_t> ground_of(scan.size(), -1);
  std::vector<bool> is_ground_plane(analysis.planes.planes.size(), false);
  for (int g : analysis.ground_planes)
    is_ground_plane[std::size_t(g)] = true;
  for (std::size_t i = 0; i < scan.size(); ++i)
    if (point_plane[i] >= 0 && is_ground_plane[std::size_t(point_plane[i])])
      ground_of[i] = point_plane[i];
  return ground_of;
}

// Every valid point in the map frame, and the box of the ground seen within `max_extent` of the
// scanner. Floats: within max_extent (<= 500 m) they keep better than 0.1 mm, at half the memory
// of doubles.
struct MappedPoints {
  std::vector<Eigen::Vector3f> positions;
  Eigen::AlignedBox2d ground_box;
};

MappedPoints pointsInMapFrame(const Scan& scan, const Eigen::Isometry3d& map_from_scanner,
                              const std::vector<std::int32_t>& ground_of, double max_extent,
                              int threads) {
  MappedPoints mapped;
  mapped.positions.resize(scan.size());
  detail::PerPart<Eigen::AlignedBox2d> boxes(std::size_t(std::max(threads, 1)));
  detail::parallelChunks(scan.size(), threads,
                         [&](std::size_t begin, std::size_t end, std::size_t chunk) {
                           for (std::size_t i = begin; i < end; ++i) {
                             if (!scan.isValid(i)) continue;
                             const Point3f& p = scan.points[i];
                             Eigen::Vector3f& m = mapped.positions[i];
                             m = (map_from_scanner * Eigen::Vector3d(p.x, p.y, p.z)).cast<float>();
                             if (ground_of[i] >= 0 && m.head<2>().norm() <= max_extent)
                               boxes[chunk].extend(m.head<2>().cast<double>());
                           }
                         });
  for (const Eigen::AlignedBox2d& box : boxes)
    if (!box.isEmpty()) mapped.ground_box.extend(box);
  return mapped;
}

// The grid over the ground seen, the robot's own place and the staircases, with a thin rim.
MapGrid gridOver(Eigen::AlignedBox2d box, const StairDetection& stairs, double resolution) {
  if (box.isEmpty()) box.extend(Eigen::Vector2d::Zero());
  // The robot stands around the scanner's foot (the map origin), where the scan often saw no
  // floor: the grid always holds its own place, whatever robot the map is computed for.
  box.extend(Eigen::Vector2d::Constant(kOwnPlaceExtent));
  box.extend(Eigen::Vector2d::Constant(-kOwnPlaceExtent));
  // Staircases too: their upper steps may be seen from below only, with no ground around them.
  for (const Staircase& staircase : stairs.staircases)
    for (const Eigen::Vector2d& corner : staircase.footprint())
      box.extend(corner);
  // A thin rim around the ground, the same for every robot so that a re-run for a new size keeps
  // the grid. Nothing outside it was observed ground, and cells outside the grid count as blocked.
  MapGrid grid;
  grid.resolution = resolution;
  grid.origin = (box.min().array() - kMapMargin).matrix();
  grid.width = int(std::ceil((box.max().x() - box.min().x() + 2 * kMapMargin) / resolution)) + 1;
  grid.height = int(std::ceil((box.max().y() - box.min().y() + 2 * kMapMargin) / resolution)) + 1;
  return grid;
}

// Each valid point's cell, once.
std::vector<Eigen::Vector2i> cellsOfPoints(const Scan& scan,
                                           const std::vector<Eigen::Vector3f>& mapped,
                                           const MapGrid& grid, int threads) {
  std::vector<Eigen::Vector2i> cell_of(scan.size(), Eigen::Vector2i::Zero());
  detail::parallelChunks(scan.size(), threads,
                         [&](std::size_t begin, std::size_t end, std::size_t) {
                           for (std::size_t i = begin; i < end; ++i)
                             if (scan.isValid(i))
                               cell_of[i] = grid.cellOf(mapped[i].x(), mapped[i].y());
                         });
  return cell_of;
}

// Per plane, its map height coefficients (ScanAnalysis::height_coefficients) when it is ground,
// else NaN (EdgeLimit::plane_heights).
std::vector<Eigen::Vector3d> groundPlaneHeights(const ScanAnalysis& analysis) {
  std::vector<Eigen::Vector3d> heights(analysis.planes.planes.size(),
                                       Eigen::Vector3d::Constant(std::nan("")));
  for (const int g : analysis.ground_planes)
    heights[std::size_t(g)] = analysis.height_coefficients[std::size_t(g)];
  return heights;
}

// How ground that no plane took in may continue a ground plane: flat where nothing in a cell
// rises above ground noise (obstacle_min_height) within the robot's band; from one return to the
// next no steeper than a drivable slope (plus 2 cm: 1 cm range noise on either) and never a rise
// that would be an obstacle's return itself; at most a robot's step off the plane, so that
// whatever it reaches is a surface the robot could step onto from the plane anyway.
detail::GroundContinuationLimits continuationLimits(const SegmentationParams& params) {
  detail::GroundContinuationLimits limits;
  limits.flatness = float(params.map.obstacle_min_height);
  limits.clear_height = float(params.robot.height);
  limits.noise = 0.02F;
  limits.slope = float(std::tan(params.ground.max_slope_deg * std::numbers::pi / 180.0));
  limits.off_plane = float(params.robot.max_step);
  return limits;
}

// A ground cell's height is the local ground's: its own points' lowest, or the triangle over it,
// not its plane's (an outdoor plane is only an approximation of the road far from its centre).
// The first to mark a cell keeps it: false when it was marked already.
bool markGround(MapInputs& inputs, int column, int row, int plane, float height) {
  if (!inputs.grid.inside(column, row)) return false;
  const std::size_t cell = inputs.grid.index(column, row);
  if (inputs.ground_plane[cell] >= 0) return false;
  inputs.ground_plane[cell] = std::int16_t(plane);
  inputs.ground_height[cell] = height;
  return true;
}

// Cells holding ground points, at the lowest of the cell's ground points of its plane: the
// support band also takes in the foot of a low obstacle, which must not raise the ground it is
// measured against.
void markGroundPointCells(MapInputs& inputs, const std::vector<std::int32_t>& ground_of,
                          const std::vector<Eigen::Vector3f>& mapped,
                          const std::vector<Eigen::Vector2i>& cell_of) {
  const MapGrid& grid = inputs.grid;
  std::vector<float> lowest(grid.cells(), std::numeric_limits<float>::max());
  for (std::size_t i = 0; i < ground_of.size(); ++i) {
    if (ground_of[i] < 0) continue;
    markGround(inputs, cell_of[i].x(), cell_of[i].y(), ground_of[i], 0.0F);
    if (!grid.inside(cell_of[i].x(), cell_of[i].y())) continue;
    const std::size_t cell = grid.index(cell_of[i].x(), cell_of[i].y());
    if (inputs.ground_plane[cell] != ground_of[i]) continue;
    lowest[cell] = std::min(lowest[cell], mapped[i].z());
  }
  for (std::size_t cell = 0; cell < grid.cells(); ++cell)
    if (lowest[cell] < std::numeric_limits<float>::max()) inputs.ground_height[cell] = lowest[cell];
}

// The triangles (scan point indices) as a mesh whose vertices know their cells, vertices in the
// order of their points.
GroundMesh meshOf(std::vector<std::array<std::uint32_t, 3>> triangles,
                  const std::vector<Eigen::Vector2i>& cell_of, const MapGrid& grid, int threads) {
  // The corners' points marked in parallel (every store writes the same 1), numbered in order,
  // and the triangles' corners replaced by those numbers in parallel.
  std::vector<std::uint32_t> vertex_of(cell_of.size(), 0);
  detail::parallelChunks(
      triangles.size(), threads, [&](std::size_t begin, std::size_t end, std::size_t) {
        for (std::size_t t = begin; t < end; ++t)
          for (const std::uint32_t point : triangles[t])
            std::atomic_ref<std::uint32_t>(vertex_of[point]).store(1, std::memory_order_relaxed);
      });
  GroundMesh mesh;
  const std::size_t vertices =
      vertex_of.size() - std::size_t(std::count(vertex_of.begin(), vertex_of.end(), 0U));
  mesh.points.reserve(vertices);
  mesh.cells.reserve(vertices);
  for (std::size_t point = 0; point < vertex_of.size(); ++point) {
    if (!vertex_of[point]) continue;
    vertex_of[point] = std::uint32_t(mesh.points.size());
    mesh.points.push_back(std::uint32_t(point));
    const Eigen::Vector2i& cell = cell_of[point];
    mesh.cells.push_back(grid.inside(cell.x(), cell.y())
                             ? std::uint32_t(grid.index(cell.x(), cell.y()))
                             : GroundMesh::kOutsideGrid);
  }
  detail::parallelChunks(triangles.size(), threads,
                         [&](std::size_t begin, std::size_t end, std::size_t) {
                           for (std::size_t t = begin; t < end; ++t)
                             for (std::uint32_t& corner : triangles[t])
                               corner = vertex_of[corner];
                         });
  mesh.triangles = std::move(triangles);
  return mesh;
}

// The cells the ground triangles cover, at the triangle's height over each cell centre.
void markTriangleCells(MapInputs& inputs, const std::vector<std::int32_t>& ground_of,
                       const detail::EdgeLimit& limit, const std::vector<Eigen::Vector2i>& cell_of,
                       int threads) {
  const std::vector<Eigen::Vector3f>& mapped = limit.mapped;
  const MapGrid& grid = inputs.grid;
  const GroundMesh& mesh = inputs.ground_mesh;
  auto pointsOf = [&mesh](std::size_t t) {
    const std::array<std::uint32_t, 3>& corners = mesh.triangles[t];
    return std::array<std::uint32_t, 3>{mesh.points[corners[0]], mesh.points[corners[1]],
                                        mesh.points[corners[2]]};
  };
  // Most triangles lie within two neighbouring cells, which their corners have marked already;
  // only the larger ones are filled, band of grid rows by band: each band is one task's (no cell
  // is written twice) and holds its triangles in triangle order, so the result does not depend on
  // the number of threads. Several bands per thread: a multi-beam frame's large triangles crowd
  // the rows around the car (with one band per thread, 12.2 ms on one thread gave 8.6 on two).
  constexpr std::size_t kBandsPerThread = 4;
  const std::size_t bands = detail::chunkCount(std::size_t(grid.height), threads, kBandsPerThread);
  // Band b holds rows [height * b / bands, height * (b + 1) / bands): a row's band is the last
  // whose first row is not after it.
  auto bandOf = [&](int row) {
    return (std::size_t(row + 1) * bands - 1) / std::size_t(grid.height);
  };
  auto rowsOf = [&](const std::array<std::uint32_t, 3>& triangle) {
    const int a = cell_of[triangle[0]].y(), b = cell_of[triangle[1]].y(),
              c = cell_of[triangle[2]].y();
    return std::pair{std::min({a, b, c}), std::max({a, b, c})};
  };
  // The cells of triangle t whose centres it covers, in rows [row_begin, row_end).
  auto fillTriangle = [&](std::uint32_t t, int row_begin, int row_end) {
    const std::array<std::uint32_t, 3> triangle = pointsOf(t);
    const auto [low_row, high_row] = rowsOf(triangle);
    // Scanline fill: per row, the triangle's x-interval at the row's centre line.
    const Eigen::Vector2d corners[3] = {mapped[triangle[0]].head<2>().cast<double>(),
                                        mapped[triangle[1]].head<2>().cast<double>(),
                                        mapped[triangle[2]].head<2>().cast<double>()};
    // The triangle's height over the map: z = h0 + hx x + hy y through its corners, from
    // its normal (closed form: a QR solve per triangle was a tenth of a multi-beam frame's
    // time). A triangle flat in x-y covers no cell centre; it keeps its first corner's z.
    // A triangle joining two ground planes spans their step over the cells it fills.
    // A long triangle of one plane may hide a step in what it bridges. Worked out at the first
    // cell it fills: on a multi-beam frame most large triangles only cross cells filled already,
    // and the two steps were a quarter of this stage's instructions.
    float joined_step = -1.0F;
    auto stepOfTriangle = [&] {
      if (joined_step < 0.0F) {
        joined_step = float(limit.joinedStep(ground_of, triangle[0], triangle[1], triangle[2]));
        if (joined_step == 0.0F)
          joined_step = float(limit.spannedStep(ground_of, triangle[0], triangle[1], triangle[2]));
      }
      return joined_step;
    };
    const Eigen::Vector3d p0 = mapped[triangle[0]].cast<double>();
    const Eigen::Vector3d normal =
        (mapped[triangle[1]].cast<double>() - p0).cross(mapped[triangle[2]].cast<double>() - p0);
    Eigen::Vector3d h(p0.z(), 0.0, 0.0);
    if (std::abs(normal.z()) > 1e-12) {
      h[1] = -normal.x() / normal.z();
      h[2] = -normal.y() / normal.z();
      h[0] = p0.z() - h[1] * p0.x() - h[2] * p0.y();
    }
    for (int row = std::max(low_row, row_begin); row <= std::min(high_row, row_end - 1); ++row) {
      const double y = grid.origin.y() + (row + 0.5) * grid.resolution;
      double x_min = std::numeric_limits<double>::max(),
             x_max = std::numeric_limits<double>::lowest();
      for (int e = 0; e < 3; ++e) {
        const Eigen::Vector2d& p = corners[e];
        const Eigen::Vector2d& q = corners[(e + 1) % 3];
        if ((p.y() - y) * (q.y() - y) > 0.0 || p.y() == q.y()) continue;  // edge misses the line
        const double x = p.x() + (y - p.y()) * (q.x() - p.x()) / (q.y() - p.y());
        x_min = std::min(x_min, x);
        x_max = std::max(x_max, x);
      }
      if (x_min > x_max) continue;
      const int first = int(std::ceil((x_min - grid.origin.x()) / grid.resolution - 0.5));
      const int last = int(std::floor((x_max - grid.origin.x()) / grid.resolution - 0.5));
      for (int column = first; column <= last; ++column) {
        const Eigen::Vector2d centre = grid.centre(column, row);
        if (markGround(inputs, column, row, ground_of[triangle[0]],
                       float(h[0] + h[1] * centre.x() + h[2] * centre.y())) &&
            stepOfTriangle() > 0.0F)
          inputs.seam_step[grid.index(column, row)] = joined_step;
      }
    }
  };
  const std::size_t parts = detail::chunkCount(mesh.triangles.size(), threads);
  // Per part of the triangles, per band: the large triangles that reach into the band.
  std::vector<std::vector<std::vector<std::uint32_t>>> large(
      parts, std::vector<std::vector<std::uint32_t>>(bands));
  detail::parallelChunks(
      mesh.triangles.size(), threads, [&](std::size_t begin, std::size_t end, std::size_t part) {
        for (std::size_t t = begin; t < end; ++t) {
          const std::array<std::uint32_t, 3> triangle = pointsOf(t);
          const Eigen::Vector2i &a = cell_of[triangle[0]], &b = cell_of[triangle[1]],
                                &c = cell_of[triangle[2]];
          const Eigen::Vector2i span = a.cwiseMax(b).cwiseMax(c) - a.cwiseMin(b).cwiseMin(c);
          if (span.maxCoeff() <= 1 && span.minCoeff() <= 0) continue;
          const auto [low_row, high_row] = rowsOf(triangle);
          if (high_row < 0 || low_row >= grid.height) continue;  // no row of the grid
          const std::size_t first = bandOf(std::max(low_row, 0)),
                            last = bandOf(std::min(high_row, grid.height - 1));
          for (std::size_t band = first; band <= last; ++band)
            large[part][band].push_back(std::uint32_t(t));
        }
      });
  detail::parallelChunks(
      bands, threads,
      [&](std::size_t band_begin, std::size_t band_end, std::size_t) {
        for (std::size_t band = band_begin; band < band_end; ++band) {
          const int row_begin = int(std::size_t(grid.height) * band / bands);
          const int row_end = int(std::size_t(grid.height) * (band + 1) / bands);
          for (const auto& part : large)
            for (const std::uint32_t t : part[band])
              fillTriangle(t, row_begin, row_end);
        }
      },
      kBandsPerThread);
}

// A single unobserved cell inside observed ground (a beam that fell between two cells) is ground
// too when at least this many of its eight neighbours are ground of one plane.
constexpr int kHoleNeighbours = 5;

void markSingleHoles(MapInputs& inputs) {
  const MapGrid& grid = inputs.grid;
  // Ground cells per 3 x 3 block, of any plane, first (sums of rows of three, then of columns):
  // most unobserved cells have none around them, and need no count per plane.
  const std::size_t width = std::size_t(grid.width);
  std::vector<std::uint8_t> across(grid.cells(), 0);
  for (int row = 0; row < grid.height; ++row) {
    const std::int16_t* plane = inputs.ground_plane.data() + std::size_t(row) * width;
    std::uint8_t* sum = across.data() + std::size_t(row) * width;
    for (std::size_t column = 1; column + 1 < width; ++column)
      sum[column] =
          std::uint8_t((plane[column - 1] >= 0) + (plane[column] >= 0) + (plane[column + 1] >= 0));
  }
  std::vector<std::pair<std::size_t, int>> holes;
  for (int row = 1; row + 1 < grid.height; ++row) {
    const std::uint8_t* above = across.data() + std::size_t(row - 1) * width;
    const std::uint8_t* here = above + width;
    const std::uint8_t* below = here + width;
    for (int column = 1; column + 1 < grid.width; ++column) {
      if (above[column] + here[column] + below[column] < kHoleNeighbours) continue;
      if (inputs.ground_plane[grid.index(column, row)] >= 0) continue;
      // Count the neighbours' planes in a small array.
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
        if (counts[k] >= kHoleNeighbours) holes.emplace_back(grid.index(column, row), planes[k]);
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
    markGround(inputs, column, row, plane, height / float(std::max(neighbours, 1)));
  }
}

// Per cell, how many of the sensor's steps along a line its ground samples may lie apart: 1, or
// where a triangle bridging lost returns may cover it (every cell of its bounds), its
// steps_apart.
std::vector<std::uint8_t> stepsApartAlongLines(const std::vector<detail::BridgedTriangle>& bridged,
                                               const std::vector<Eigen::Vector2i>& cell_of,
                                               const MapGrid& grid) {
  std::vector<std::uint8_t> steps(grid.cells(), 1);
  for (const detail::BridgedTriangle& triangle : bridged) {
    Eigen::AlignedBox2i box;
    for (const std::uint32_t corner : triangle.corners)
      box.extend(cell_of[corner]);
    const int first_column = std::max(box.min().x(), 0),
              last_column = std::min(box.max().x(), grid.width - 1);
    const int first_row = std::max(box.min().y(), 0),
              last_row = std::min(box.max().y(), grid.height - 1);
    for (int row = first_row; row <= last_row; ++row)
      for (int column = first_column; column <= last_column; ++column) {
        std::uint8_t& here = steps[grid.index(column, row)];
        here = std::max(here, triangle.steps_apart);
      }
  }
  return steps;
}

// What could hide between the ground samples of each ground cell (docs/ALGORITHM.md): from the
// sensor's angular steps at that range, along a line `steps_apart` of them where returns were lost.
std::vector<float> groundSpacing(const MapInputs& inputs, const ScanAnalysis& analysis,
                                 const std::vector<std::uint8_t>& steps_apart, int threads) {
  const MapGrid& grid = inputs.grid;
  const Eigen::Isometry3d scanner_from_map = analysis.map_from_scanner.inverse();
  const double scanner_z = analysis.map_from_scanner.translation().z();
  // The sensor as sparse as its lost returns leave it: index = steps apart along a line.
  std::array<SensorGeometry, detail::kLostReturnsBridged + 2> sensors;
  for (std::size_t steps = 1; steps < sensors.size(); ++steps) {
    sensors[steps] = analysis.sensor;
    sensors[steps].along_line_step *= double(steps);
  }
  std::vector<float> spacing(grid.cells(), std::numeric_limits<float>::infinity());
  // A few dozen operations per ground cell, and a multi-beam frame's map has hundreds of
  // thousands: the rows are dealt out to the threads.
  detail::parallelChunks(
      std::size_t(grid.height), threads,
      [&](std::size_t row_begin, std::size_t row_end, std::size_t) {
        for (int row = int(row_begin); row < int(row_end); ++row)
          for (int column = 0; column < grid.width; ++column) {
            const std::size_t cell = grid.index(column, row);
            if (inputs.ground_plane[cell] < 0) continue;
            const Eigen::Vector2d centre = grid.centre(column, row);
            const Eigen::Vector3d ground(centre.x(), centre.y(), inputs.ground_height[cell]);
            spacing[cell] =
                float(hiddenObstacleSize(sensors[steps_apart[cell]], scanner_from_map * ground,
                                         analysis.up, scanner_z - inputs.ground_height[cell]));
          }
      });
  return spacing;
}

// The ground under a point in a cell with no ground near it (hidden under an obstacle): the
// highest ground plane below the point whose real area reaches there, or the reference plane.
double groundBeneathHidden(const ScanAnalysis& analysis, const Eigen::Isometry3d& scanner_from_map,
                           const Eigen::Vector3d& m) {
  // A plane counts as below the point up to this much above it (the point may lie in its band).
  constexpr double kPlaneBand = 0.05;  // [m]
  double ground = analysis.planeHeight(analysis.reference_ground, m.x(), m.y());
  for (int g : analysis.ground_planes) {
    const double h = analysis.planeHeight(g, m.x(), m.y());
    if (h <= m.z() + kPlaneBand && h > ground &&
        analysis.planes.supports[std::size_t(g)].contains(scanner_from_map *
                                                          Eigen::Vector3d(m.x(), m.y(), h)))
      ground = h;
  }
  return ground;
}

// Every point that is not ground (`points`: the valid non-ground points inside the grid, in point
// order), with its height above the ground beneath it, written in place (no second copy of a
// scan's worth of obstacles).
std::vector<MapObstacle> measureObstacles(const ScanAnalysis& analysis, const MapInputs& inputs,
                                          const std::vector<std::uint32_t>& points,
                                          const std::vector<Eigen::Vector3f>& mapped, int threads) {
  const MapGrid& grid = inputs.grid;
  const Eigen::Isometry3d scanner_from_map = analysis.map_from_scanner.inverse();
  const std::vector<float> ground_around = lowestGroundAround(inputs);
  std::vector<MapObstacle> obstacles(points.size());
  detail::parallelChunks(points.size(), threads,
                         [&](std::size_t begin, std::size_t end, std::size_t) {
                           for (std::size_t e = begin; e < end; ++e) {
                             const std::size_t i = points[e];
                             const Eigen::Vector3d m = mapped[i].cast<double>();
                             const Eigen::Vector2i cell = grid.cellOf(mapped[i].x(), mapped[i].y());
                             const std::size_t index = grid.index(cell.x(), cell.y());
                             double ground = 0.0;
                             if (inputs.ground_plane[index] >= 0)
                               ground = inputs.ground_height[index];
                             else if (std::isfinite(ground_around[index]))
                               ground = ground_around[index];
                             else
                               ground = groundBeneathHidden(analysis, scanner_from_map, m);
                             obstacles[e] = {std::uint32_t(index), float(m.x()), float(m.y()),
                                             float(m.z()), float(m.z() - ground)};
                           }
                         });
  return obstacles;
}

// Each obstacle's neighbouring beams across the sweep (SweepNeighbours). `partners.points()` are
// the obstacles' points, as measureObstacles keeps them: an entry's index is its obstacle's.
// Obstacles are dealt out to the threads in ranges, each numbering its beams from 0; the ranges'
// beams are then laid end to end in order and the later ranges' numbers moved up, so the result
// does not depend on the number of threads.
SweepNeighbours sweepNeighbours(const Scan& scan, const detail::SweepPartners& partners,
                                const std::vector<Eigen::Vector3f>& mapped,
                                const Eigen::Vector3f& scanner, int threads) {
  SweepNeighbours neighbours;
  const std::size_t obstacles = partners.points().size();
  if (partners.partners.size() != obstacles) return neighbours;
  neighbours.of_obstacle.assign(obstacles, {SweepNeighbours::kNone, SweepNeighbours::kNone});
  detail::PerPart<std::vector<SweepNeighbours::Beam>> beams(detail::chunkCount(obstacles, threads));
  detail::parallelChunks(
      obstacles, threads, [&](std::size_t begin, std::size_t end, std::size_t chunk) {
        for (std::size_t obstacle = begin; obstacle < end; ++obstacle) {
          const std::size_t i = partners.points()[obstacle];
          const float range = (mapped[i] - scanner).norm();
          for (std::size_t side = 0; side < 2; ++side) {
            const std::uint32_t q = partners.partners[obstacle][side];
            if (q == detail::kNoPartner || !scan.isValid(q)) continue;
            if (const std::uint32_t other = partners.entryOf(q); other != detail::kNoPartner) {
              neighbours.of_obstacle[obstacle][side] = other;
              continue;
            }
            // The neighbouring beam at this obstacle's range from the scanner.
            const Eigen::Vector3f beam = mapped[q] - scanner;
            const float length = beam.norm();
            if (!(length > 0.0F)) continue;
            const Eigen::Vector3f pass = scanner + beam * (range / length);
            neighbours.of_obstacle[obstacle][side] =
                SweepNeighbours::kBeam | std::uint32_t(beams[chunk].size());
            beams[chunk].push_back({pass.x(), pass.y(), pass.z(), length - range});
          }
        }
      });
  std::size_t total = 0;
  for (const auto& part : beams)
    total += part.size();
  neighbours.beams.reserve(total);
  for (std::size_t chunk = 0; chunk < beams.size(); ++chunk) {
    const auto offset = std::uint32_t(neighbours.beams.size());
    neighbours.beams.insert(neighbours.beams.end(), beams[chunk].begin(), beams[chunk].end());
    detail::releaseMemory(beams[chunk]);
    if (offset == 0) continue;
    const std::size_t begin = obstacles * chunk / beams.size(),
                      end = obstacles * (chunk + 1) / beams.size();
    for (std::size_t obstacle = begin; obstacle < end; ++obstacle)
      for (std::uint32_t& entry : neighbours.of_obstacle[obstacle])
        if (entry != SweepNeighbours::kNone && (entry & SweepNeighbours::kBeam)) entry += offset;
  }
  return neighbours;
}

}  // namespace

MapInputs prepareMapInputs(const Scan& scan, const SegmentationParams& params,
                           const ScanAnalysis& analysis, int threads) {
  MapInputs inputs;
  if (!analysis.ground_found) return inputs;
  const Eigen::Isometry3d& map_from_scanner = analysis.map_from_scanner;
  const double scanner_z = map_from_scanner.translation().z();
  // How high the scanner looked needs nothing below: it is worked out on the other thread, where
  // that thread would otherwise wait for this one's serial steps.
  ViewLimit view;
  detail::BackgroundTask view_search(
      [&] { view = detail::viewLimitOf(scan, analysis.sensor, map_from_scanner, 1); }, threads);

  std::vector<std::int32_t> ground_of = groundOfPoints(scan, analysis);
  const MappedPoints mapped =
      pointsInMapFrame(scan, map_from_scanner, ground_of, params.map.max_extent, threads);
  inputs.grid = gridOver(mapped.ground_box, analysis.stairs, params.map.resolution);
  inputs.ground_plane.assign(inputs.grid.cells(), -1);
  inputs.ground_height.assign(inputs.grid.cells(), 0.0F);
  inputs.seam_step.assign(inputs.grid.cells(), 0.0F);
  std::vector<Eigen::Vector2i> cell_of =
      cellsOfPoints(scan, mapped.positions, inputs.grid, threads);

  detail::EdgeLimit limit{mapped.positions,
                          analysis.sensor,
                          params.map.max_triangle_edge,
                          std::max(detail::kLowestScannerHeight, scanner_z),
                          params.robot.max_step,
                          groundPlaneHeights(analysis)};
  // Which lines lie side by side, and how their points pair up.
  const detail::LinePairing pairing(scan, ground_of, analysis.sensor, scanner_z, threads);
  // Ground no plane took in, continued from the planes' along and across the lines, as far apart
  // as the ground triangles may join returns.
  detail::ContinuedGround continued = detail::continueGround(
      std::move(ground_of), scan, pairing, analysis.planes.point_plane, mapped.positions, cell_of,
      inputs.grid, limit.plane_heights, continuationLimits(params),
      [&limit](std::size_t point) { return limit.maxEdgeSquared(point); });
  ground_of = std::move(continued.ground_of);
  limit.continued = std::move(continued.continued);
  // Returns on a low box's face that joined the floor plane's band are the face, not the floor.
  detail::dropFaceReturns(ground_of, scan, mapped.positions, limit.plane_heights);

  // Ground: the cells holding ground points, then those the ground triangles cover, then single
  // holes; the first to mark a cell sets its height.
  markGroundPointCells(inputs, ground_of, mapped.positions, cell_of);
  // The points measureObstacles will keep, whose partners across the sweep are wanted.
  auto obstacle = [&](std::size_t i) {
    return scan.isValid(i) && ground_of[i] < 0 &&
           inputs.grid.inside(cell_of[i].x(), cell_of[i].y());
  };
  std::vector<std::uint32_t> obstacle_points;
  std::size_t obstacles = 0;  // counted first: half a dense scan's points, not grown by doubling
  for (std::size_t i = 0; i < scan.size(); ++i)
    obstacles += std::size_t(obstacle(i));
  obstacle_points.reserve(obstacles);
  for (std::size_t i = 0; i < scan.size(); ++i)
    if (obstacle(i)) obstacle_points.push_back(std::uint32_t(i));
  detail::SweepPartners partners(std::move(obstacle_points), scan.size());
  std::vector<detail::BridgedTriangle> bridged;
  inputs.ground_mesh =
      meshOf(detail::groundTriangles(scan, pairing, ground_of, limit, threads, &partners, &bridged),
             cell_of, inputs.grid, threads);
  markTriangleCells(inputs, ground_of, limit, cell_of, threads);
  // Per-point buffers are freed as soon as they are done with: the run's memory peaks as the
  // obstacles, the largest part of a dense scan's map inputs, are made last.
  detail::releaseMemory(ground_of);
  markSingleHoles(inputs);
  detail::markPlaneEdges(inputs, limit.plane_heights, analysis.planes.planes);

  inputs.ground_spacing =
      groundSpacing(inputs, analysis, stepsApartAlongLines(bridged, cell_of, inputs.grid), threads);
  detail::releaseMemory(bridged);
  detail::releaseMemory(cell_of);  // measureObstacles finds its points' cells again
  inputs.sweep_neighbours = sweepNeighbours(scan, partners, mapped.positions,
                                            map_from_scanner.translation().cast<float>(), threads);
  detail::releaseMemory(partners.partners);  // before the obstacles are made
  inputs.obstacles =
      measureObstacles(analysis, inputs, partners.points(), mapped.positions, threads);
  inputs.contacts = detail::groundContacts(inputs);
  inputs.floor_crossings = detail::floorCrossings(
      scan, analysis.sensor, map_from_scanner, inputs.grid, inputs.ground_plane, inputs.obstacles);
  view_search.join();
  inputs.view = std::move(view);
  return inputs;
}

}  // namespace clearway
