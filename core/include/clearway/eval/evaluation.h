#pragma once

// Scores a segmentation result (a `clearway-cli segment` output folder) against the simulator's
// ground truth: point classes, planes, and — what matters for safety — map cells shown
// traversable where the robot's centre cannot truly be.

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "clearway/point_class.h"
#include "clearway/segmentation/scan_analysis.h"
#include "clearway/sim/rosi_simulator.h"

namespace clearway::eval {

// What evaluate() reads from a result folder (docs/FORMATS.md, "segment output").
struct ResultMap {
  double resolution = 0.05;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  // map x, y of the lower-left cell's corner
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> labels;  // row 0 = top (largest map y)
  Eigen::Isometry3d map_from_scanner = Eigen::Isometry3d::Identity();
  std::uint8_t at(int column, int row_from_bottom) const {
    return labels[std::size_t(height - 1 - row_from_bottom) * std::size_t(width) +
                  std::size_t(column)];
  }
};

struct ResultPlane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // scanner frame
  double offset = 0.0;                                // n . p = offset
  std::string kind;
};

struct SegmentationResult {
  std::string scan;  // the scan's file name, as report.json gives it
  sim::RobotBox robot;
  std::vector<ResultPlane> planes;
  std::vector<PointClass> point_classes;  // empty when the folder has none
  ResultMap map;
  bool has_map = false;
  bool ground_found = false;
};

// Throws std::runtime_error naming the file and the problem.
SegmentationResult loadSegmentationResult(const std::filesystem::path& folder);

struct ClassScore {
  PointClass point_class = PointClass::kNone;
  std::size_t truth = 0, predicted = 0, both = 0;
  double precision = 0.0, recall = 0.0, iou = 0.0;
};

struct PlaneScore {
  std::size_t truth_planes = 0;  // planar truth surfaces with enough points
  std::size_t matched = 0;       // of those, with a result plane within tolerance
  std::size_t result_planes = 0;
  std::size_t result_matched = 0;  // result planes that match some truth surface
  double recall = 0.0;
  double precision = 0.0;
  double mean_normal_error_deg = 0.0;
  double mean_offset_error_m = 0.0;
};

struct PlaceCheck {
  std::string from, to;
  bool expected = false;  // the analytic answer for the result's robot
  bool found = false;     // joined by traversable cells in the map
};

struct MapScore {
  std::size_t traversable_cells = 0;        // labels 1 and 2
  std::size_t false_traversable_cells = 0;  // of those, where the robot cannot truly stand
  double false_traversable_rate = 0.0;
  std::vector<Eigen::Vector3d> false_cells;  // world positions of the first false cells
  std::vector<PlaceCheck> places;
};

struct EvaluationOptions {
  std::size_t min_surface_points = 200;  // smaller truth surfaces are not counted as planes
  double max_normal_error_deg = 10.0;
  double max_offset_error_m = 0.15;
  // The truth robot is this much smaller on each side than the result's, so a cell the map
  // places a few centimetres too close to a wall is not called false.
  double footprint_tolerance_m = 0.05;
  int orientations = 24;
};

struct Evaluation {
  std::array<ClassScore, kPointClassCount> classes{};
  bool has_point_classes = false;
  PlaneScore planes;
  MapScore map;
  bool has_map = false;
};

Evaluation evaluate(const sim::GroundTruth& truth, const SegmentationResult& result,
                    const EvaluationOptions& options = {});

// The parts of evaluate(), for results that are not in a folder (benchmarks, tests).
bool planesMatch(const sim::SurfaceTruth& surface, const ResultPlane& plane,
                 const EvaluationOptions& options, double& normal_error, double& offset_error);
PlaneScore scorePlanes(const sim::GroundTruth& truth, const std::vector<ResultPlane>& planes,
                       const EvaluationOptions& options = {});
MapScore scoreMap(const sim::GroundTruth& truth, const SegmentationResult& result,
                  const EvaluationOptions& options = {});

// A map in memory (row 0 = smallest map y, as TraversabilityMap keeps it) as evaluate() reads it.
ResultMap resultMapOf(const MapGrid& grid, const std::vector<std::uint8_t>& labels_bottom_up,
                      const Eigen::Isometry3d& map_from_scanner);

std::string toText(const Evaluation& evaluation);
std::string toJson(const Evaluation& evaluation);

}  // namespace clearway::eval
