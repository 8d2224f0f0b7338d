#pragma once

// Stage 6 (paper II-E): the 3D scene the operator sees, as plain data the GUI hands to VTK: the
// drivable ground as triangles coloured by the map, walls as red cuboids, obstacles as small cubes.
// Everything is in the scanner frame.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "clearway/scan.h"
#include "clearway/segmentation/scan_analysis.h"
#include "clearway/traversability/traversability_map.h"

namespace clearway {

struct SceneBox {
  Eigen::Vector3f center = Eigen::Vector3f::Zero();
  Eigen::Matrix3f axes = Eigen::Matrix3f::Identity();  // columns: the box's own x, y, z
  Eigen::Vector3f half_size = Eigen::Vector3f::Zero();
  CellLabel label = CellLabel::kImpassable;
};

struct SceneGeometry {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<CellLabel> vertex_labels;
  std::vector<std::array<std::uint32_t, 3>> triangles;  // the drivable ground
  std::vector<SceneBox> walls;                          // red cuboids, one per wall plane
  std::vector<SceneBox> obstacles;                      // cubes of obstacle points
};

// RGB of each label, shared by the PNG map, the PLY scene and the GUI.
std::array<std::uint8_t, 3> labelColour(CellLabel label);

// The 3D view's geometry; its parts are built on up to `threads` threads.
SceneGeometry buildSceneGeometry(const Scan& scan, const ScanAnalysis& analysis,
                                 const TraversabilityMap& map, const RobotParams& robot,
                                 int threads = 1);

}  // namespace clearway
