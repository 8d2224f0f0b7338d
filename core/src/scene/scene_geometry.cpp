#include "clearway/scene/scene_geometry.h"

#include <Eigen/Geometry>
#include <limits>
#include <unordered_set>

namespace clearway {
namespace {

// Obstacle cubes are this big, and there are at most this many of them.
constexpr float kCubeSize = 0.1F;
constexpr std::size_t kMaxCubes = 50'000;

CellLabel labelAt(const TraversabilityMap& map, double x, double y) {
  const Eigen::Vector2i cell = map.grid.cellOf(x, y);
  if (!map.grid.inside(cell.x(), cell.y())) return CellLabel::kUnknown;
  return map.label(cell.x(), cell.y());
}

bool drawnAsGround(CellLabel label) {
  return label == CellLabel::kTraversable || label == CellLabel::kCareful ||
         label == CellLabel::kObstacle;
}

}  // namespace

std::array<std::uint8_t, 3> labelColour(CellLabel label) {
  switch (label) {
    case CellLabel::kTraversable:
      return {46, 160, 67};
    case CellLabel::kCareful:
      return {245, 140, 20};
    case CellLabel::kObstacle:
      return {255, 183, 77};
    case CellLabel::kImpassable:
      return {211, 47, 47};
    case CellLabel::kStairs:
      return {142, 68, 173};
    case CellLabel::kUnknown:
      break;
  }
  return {60, 60, 60};
}

SceneGeometry buildSceneGeometry(const Scan& scan, const ScanAnalysis& analysis,
                                 const TraversabilityMap& map, const RobotParams& robot) {
  SceneGeometry scene;
  if (!analysis.ground_found) return scene;  // nothing drawn that cannot be trusted
  const Eigen::Isometry3d scanner_from_map = analysis.map_from_scanner.inverse();

  // Ground: the scan-grid triangles whose centre lies on a cell the robot may use.
  // Each ground point's cell label, looked up once; a triangle is drawn when at least two of its
  // corners lie on cells the robot may use.
  constexpr std::uint8_t kUnlabelled = 255;
  std::vector<std::uint8_t> point_label(scan.size(), kUnlabelled);
  auto labelOf = [&](std::uint32_t point) {
    if (point_label[point] == kUnlabelled) {
      const Point3f& p = scan.points[point];
      const Eigen::Vector3d m = analysis.map_from_scanner * Eigen::Vector3d(p.x, p.y, p.z);
      point_label[point] = std::uint8_t(labelAt(map, m.x(), m.y()));
    }
    return CellLabel(point_label[point]);
  };
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> vertex_of(scan.size(), kNone);
  auto vertex = [&](std::uint32_t point) {
    if (vertex_of[point] == kNone) {
      vertex_of[point] = std::uint32_t(scene.vertices.size());
      const Point3f& p = scan.points[point];
      scene.vertices.emplace_back(p.x, p.y, p.z);
      scene.vertex_labels.push_back(labelOf(point));
    }
    return vertex_of[point];
  };
  for (const auto& triangle : analysis.inputs.ground_triangles) {
    const int drawn = int(drawnAsGround(labelOf(triangle[0]))) +
                      int(drawnAsGround(labelOf(triangle[1]))) +
                      int(drawnAsGround(labelOf(triangle[2])));
    if (drawn < 2) continue;
    scene.triangles.push_back({vertex(triangle[0]), vertex(triangle[1]), vertex(triangle[2])});
  }

  // Walls: the supported extent of every wall plane, as a thin red cuboid.
  for (std::size_t k = 0; k < analysis.planes.planes.size(); ++k) {
    const Plane& plane = analysis.planes.planes[k];
    if (plane.kind != PlaneKind::kWall) continue;
    const SupportImage& image = analysis.planes.supports[k];
    int c0 = image.width, c1 = -1, r0 = image.height, r1 = -1;
    for (int r = 0; r < image.height; ++r)
      for (int c = 0; c < image.width; ++c)
        if (image.kept[std::size_t(r) * std::size_t(image.width) + std::size_t(c)]) {
          c0 = std::min(c0, c);
          c1 = std::max(c1, c);
          r0 = std::min(r0, r);
          r1 = std::max(r1, r);
        }
    if (c1 < 0) continue;
    const double u = image.u0 + (c0 + c1 + 1) * image.cell / 2,
                 v = image.v0 + (r0 + r1 + 1) * image.cell / 2;
    SceneBox box;
    box.center = (plane.normal * plane.offset + image.u_axis * u + image.v_axis * v).cast<float>();
    box.axes.col(0) = image.u_axis.cast<float>();
    box.axes.col(1) = image.v_axis.cast<float>();
    box.axes.col(2) = plane.normal.cast<float>();
    box.half_size = Eigen::Vector3f(float((c1 - c0 + 1) * image.cell / 2),
                                    float((r1 - r0 + 1) * image.cell / 2), 0.03F);
    scene.walls.push_back(box);
  }

  // Obstacles: one cube per occupied voxel of points between the ground and the robot's top.
  std::unordered_set<std::uint64_t> voxels;
  const Eigen::Matrix3f axes = scanner_from_map.linear().cast<float>();
  for (const MapObstacle& o : analysis.inputs.obstacles) {
    if (o.height <= 0.0F || o.height >= robot.height || scene.obstacles.size() >= kMaxCubes)
      continue;
    const auto ix = std::int64_t(std::floor(o.x / kCubeSize)),
               iy = std::int64_t(std::floor(o.y / kCubeSize)),
               iz = std::int64_t(std::floor(o.z / kCubeSize));
    const std::uint64_t key = (std::uint64_t(ix & 0x1FFFFF) << 42) |
                              (std::uint64_t(iy & 0x1FFFFF) << 21) | std::uint64_t(iz & 0x1FFFFF);
    if (!voxels.insert(key).second) continue;
    SceneBox cube;
    const Eigen::Vector3d centre((double(ix) + 0.5) * kCubeSize, (double(iy) + 0.5) * kCubeSize,
                                 (double(iz) + 0.5) * kCubeSize);
    cube.center = (scanner_from_map * centre).cast<float>();
    cube.axes = axes;
    cube.half_size = Eigen::Vector3f::Constant(kCubeSize / 2);
    cube.label = o.height <= robot.max_step ? CellLabel::kObstacle : CellLabel::kImpassable;
    scene.obstacles.push_back(cube);
  }
  return scene;
}

}  // namespace clearway
