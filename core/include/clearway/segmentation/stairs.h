#pragma once

// Stair detection (docs/ALGORITHM.md, "Stairs"): staircases found as regular runs of parallel
// risers, each a tread further on and a rise higher than the last, on a height grid of the whole
// scan in the map frame. Robot-independent: computed once per scan, judged per robot.

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "clearway/point_class.h"
#include "clearway/scan.h"
#include "clearway/segmentation/params.h"

namespace clearway {

struct MapGrid;
struct ScanAnalysis;
struct TraversabilityMap;

// One flight of stairs, in the map frame (x, y on the reference ground, z up).
struct Staircase {
  Eigen::Vector2d up = Eigen::Vector2d::UnitX();  // unit, the way the flight climbs
  Eigen::Vector2d across = Eigen::Vector2d::UnitY();
  std::vector<double> riser_offsets;          // up . (x, y) of each riser face, bottom first [m]
  std::vector<double> riser_tops;             // map z of each riser's top edge (the nosing) [m]
  double rise = 0.0;                          // fitted height per step [m]
  double tread = 0.0;                         // fitted depth per step [m]
  double across_min = 0.0, across_max = 0.0;  // extent along `across` [m]

  int steps() const { return int(riser_offsets.size()); }
  double width() const { return across_max - across_min; }
  double yawDegrees() const;                                   // direction of climb, map frame
  double slopeDegrees() const;                                 // of the flight: atan(rise / tread)
  double bottom() const { return riser_tops.front() - rise; }  // map z of the foot
  double top() const { return riser_tops.back(); }
  double start() const { return riser_offsets.front(); }       // up-offset of the first riser
  double end() const { return riser_offsets.back() + tread; }  // up-offset past the last tread
  // The four corners of the flight's footprint on the map (x, y).
  std::vector<Eigen::Vector2d> footprint() const;
  // Whether a map point (x, y, z) lies on the flight's surface (a tread or a riser).
  bool containsPoint(const Eigen::Vector3d& map_point) const;
};

// The staircases of one scan and where they lie on the map grid.
struct StairDetection {
  std::vector<Staircase> staircases;
  // Per cell of ScanAnalysis::inputs.grid: the index into `staircases` of the flight covering the
  // cell's centre, or -1. Empty when there are no staircases.
  std::vector<std::int16_t> cell_staircase;

  int staircaseAt(std::size_t cell) const {
    return cell < cell_staircase.size() ? cell_staircase[cell] : -1;
  }
};

// Finds the staircases of a scan whose map frame is known (analysis.ground_found).
std::vector<Staircase> detectStairs(const Scan& scan, const Eigen::Isometry3d& map_from_scanner,
                                    const StairParams& params);

// The per-cell staircase index for a map grid.
std::vector<std::int16_t> staircaseCells(const std::vector<Staircase>& staircases,
                                         const MapGrid& grid);

// Whether `robot` can climb a flight, and if not why (empty when it can).
std::string stairVerdict(const Staircase& staircase, const RobotParams& robot);

// One line for the console's hover readout: "4 steps, rise 17 cm, tread 29 cm, 30 deg, climbs
// towards 0 deg; climbable with care" (or why not).
std::string describeStaircase(const Staircase& staircase, const RobotParams& robot);

// Labels the cells of every staircase in `map`: kStairs when the robot can climb it (drawn as
// "stairs, climbable with care"), else impassable with reason kStairsTooSteep (or kTooNarrow).
// Never green.
void labelStairs(const ScanAnalysis& analysis, const RobotParams& robot, TraversabilityMap& map);

// Marks the points on a detected staircase as PointClass::kStairs.
void classifyStairPoints(const Scan& scan, const ScanAnalysis& analysis,
                         std::vector<PointClass>& classes);

}  // namespace clearway
