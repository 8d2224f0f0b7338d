#pragma once

// A ScanAnalysis built by hand for the traversability stage (stage 5) alone: ground cells of given
// levels and heights, obstacle points with their height above the local ground, the robot's pose.
// No scan, no simulator, no segmentation: a test on it names the stage when it fails.

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "clearway/segmentation/scan_analysis.h"

namespace clearway::test {

class HandBuiltMap {
 public:
  // A grid over [x0, x1] x [y0, y1] (map metres) with cells of `resolution`, all unobserved. Keep
  // an unobserved rim around the floor, as prepareMapInputs does (kMapMargin there): the stage
  // takes the map's edge for the end of what was seen.
  HandBuiltMap(double x0, double y0, double x1, double y1, double resolution = 0.05) {
    MapGrid& grid = analysis_.inputs.grid;
    grid.resolution = resolution;
    grid.origin = {x0, y0};
    grid.width = int(std::lround((x1 - x0) / resolution));
    grid.height = int(std::lround((y1 - y0) / resolution));
    analysis_.inputs.ground_plane.assign(grid.cells(), -1);
    analysis_.inputs.ground_height.assign(grid.cells(), 0.0F);
    // ground_spacing stays empty: every ground cell is dense enough (no "too sparse" cells).
    analysis_.ground_found = true;
    analysis_.reference_ground = 0;
    addLevel(0);
  }

  // Cells whose centres lie in [x0, x1) x [y0, y1) become observed ground of `level` (0: the
  // reference ground the robot stands on) at map height `height`.
  HandBuiltMap& floor(double x0, double y0, double x1, double y1, int level = 0,
                      double height = 0.0) {
    addLevel(level);
    const MapGrid& grid = analysis_.inputs.grid;
    for (int row = 0; row < grid.height; ++row)
      for (int column = 0; column < grid.width; ++column) {
        const Eigen::Vector2d centre = grid.centre(column, row);
        if (centre.x() < x0 || centre.x() >= x1 || centre.y() < y0 || centre.y() >= y1) continue;
        analysis_.inputs.ground_plane[grid.index(column, row)] = std::int16_t(level);
        analysis_.inputs.ground_height[grid.index(column, row)] = float(height);
      }
    return *this;
  }

  // Cells whose centres lie in [x0, x1) x [y0, y1) become observed ground of `level` on a ramp
  // rising `slope` (dz / dx) along x from height 0 at x = 0; the level's plane is that ramp.
  HandBuiltMap& ramp(double x0, double y0, double x1, double y1, int level, double slope) {
    floor(x0, y0, x1, y1, level);
    analysis_.height_coefficients[std::size_t(level)] = Eigen::Vector3d(0.0, slope, 0.0);
    const MapGrid& grid = analysis_.inputs.grid;
    for (std::size_t cell = 0; cell < grid.cells(); ++cell) {
      const auto row = int(cell / std::size_t(grid.width));
      const int column = int(cell) - row * grid.width;
      if (analysis_.inputs.ground_plane[cell] == level)
        analysis_.inputs.ground_height[cell] = float(slope * grid.centre(column, row).x());
    }
    return *this;
  }

  // One measured non-ground point at map (x, y), `height` above the local ground.
  HandBuiltMap& point(double x, double y, double height) {
    const MapGrid& grid = analysis_.inputs.grid;
    const Eigen::Vector2i cell = grid.cellOf(x, y);
    if (!grid.inside(cell.x(), cell.y())) return *this;
    const std::size_t index = grid.index(cell.x(), cell.y());
    const double ground = analysis_.inputs.ground_height[index];
    analysis_.inputs.obstacles.push_back(
        {std::uint32_t(index), float(x), float(y), float(ground + height), float(height)});
    analysis_.inputs.sweep_neighbours.of_obstacle.push_back(
        {SweepNeighbours::kNone, SweepNeighbours::kNone});
    return *this;
  }

  // The last point's neighbouring scan line across the sweep: its beam was at map (x, y),
  // `height` above the local ground there, at the point's range and went on `beyond` metres
  // farther (SweepNeighbours). Nothing between was seen.
  HandBuiltMap& sweptPast(double x, double y, double height, double beyond) {
    const MapGrid& grid = analysis_.inputs.grid;
    const Eigen::Vector2i cell = grid.cellOf(x, y);
    const double ground = grid.inside(cell.x(), cell.y())
                              ? analysis_.inputs.ground_height[grid.index(cell.x(), cell.y())]
                              : 0.0;
    SweepNeighbours& neighbours = analysis_.inputs.sweep_neighbours;
    neighbours.of_obstacle.back()[1] =
        SweepNeighbours::kBeam | std::uint32_t(neighbours.beams.size());
    neighbours.beams.push_back({float(x), float(y), float(ground + height), float(beyond)});
    return *this;
  }

  // The last point's neighbouring scan line hit the earlier point number `obstacle`.
  HandBuiltMap& sweptOnto(std::size_t obstacle) {
    analysis_.inputs.sweep_neighbours.of_obstacle.back()[1] = std::uint32_t(obstacle);
    return *this;
  }

  std::size_t points() const { return analysis_.inputs.obstacles.size(); }

  // Points densely sampled (every kSampleSpacing) on the vertical face over the segment from
  // `from` to `to`, from `low` to `high` above the ground: a wall, a riser, a lintel's face.
  HandBuiltMap& face(const Eigen::Vector2d& from, const Eigen::Vector2d& to, double low,
                     double high) {
    const int along = std::max(1, int(std::ceil((to - from).norm() / kSampleSpacing)));
    const int up = std::max(0, int(std::floor((high - low) / kSampleSpacing + 1e-9)));
    for (int a = 0; a <= along; ++a) {
      const Eigen::Vector2d at = from + (to - from) * (double(a) / along);
      for (int h = 0; h <= up; ++h)
        point(at.x(), at.y(), low + h * kSampleSpacing);
    }
    return *this;
  }

  // A horizontal slab of points over [x0, x1] x [y0, y1] at `height` above the ground: a lintel.
  HandBuiltMap& slab(double x0, double y0, double x1, double y1, double height) {
    for (double x = x0; x <= x1 + 1e-9; x += kSampleSpacing)
      face({x, y0}, {x, y1}, height, height);
    return *this;
  }

  // A standing wall plane whose face runs along map direction `yaw`: the stage tries the box along
  // and square to every wall (a narrow door is passable only square to its wall).
  HandBuiltMap& wallPlane(double yaw) {
    Plane plane;
    plane.kind = PlaneKind::kWall;
    plane.validated = true;
    plane.normal = Eigen::Vector3d(-std::sin(yaw), std::cos(yaw), 0.0);
    analysis_.planes.planes.push_back(plane);
    analysis_.height_coefficients.push_back(Eigen::Vector3d::Zero());
    return *this;
  }

  // Ground levels a and b meet with a step this high (MapInputs::contacts).
  HandBuiltMap& contact(int a, int b, double step) {
    analysis_.inputs.contacts.push_back({a, b, float(step)});
    return *this;
  }

  // The robot's pose on the map, as a pose sidecar gives it (robot_from_scanner, with the scanner
  // at the map's origin).
  HandBuiltMap& robotAt(double x, double y, double yaw) {
    const Eigen::Isometry3d map_from_robot =
        Eigen::Translation3d(x, y, 0.0) * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ());
    analysis_.robot_from_scanner = map_from_robot.inverse();
    return *this;
  }

  const ScanAnalysis& analysis() const { return analysis_; }

  // Measured points lie this far apart on a face: denser than a cell, as a near scan's are [m].
  static constexpr double kSampleSpacing = 0.01;

 private:
  // Ground levels are horizontal ground planes: plane `level` of the analysis.
  void addLevel(int level) {
    auto& planes = analysis_.planes.planes;
    while (int(planes.size()) <= level) {
      Plane plane;
      plane.kind = PlaneKind::kGround;
      plane.validated = true;
      planes.push_back(plane);
      analysis_.ground_planes.push_back(int(planes.size()) - 1);
      analysis_.height_coefficients.push_back(Eigen::Vector3d::Zero());
    }
  }

  ScanAnalysis analysis_;
};

}  // namespace clearway::test
