#include "clearway/scene/scene_geometry.h"

#include <Eigen/Geometry>
#include <limits>
#include <unordered_set>
#include <vector>

#include "../segmentation/parallel.h"

namespace clearway {
namespace {

// Obstacle cubes are this big, and there are at most this many of them.
constexpr float kCubeSize = 0.1F;
constexpr std::size_t kMaxCubes = 50'000;
// Wall boxes: 6 cm thick; a plane whose normal is this close to vertical is no wall in the map
// frame; wall pieces lower than this (a ceiling's crossing), or ceilings lower than this, are not
// drawn / not used for clipping [m].
constexpr float kWallHalfThickness = 0.03F;
constexpr double kMinHorizontalNormal = 0.3;
constexpr double kMinWallHeight = 0.25;
// Walls stop this far below the ceiling so the ceiling's points stay visible above them [m].
constexpr double kCeilingClearance = 0.02;
// A wall whose supported cells reach this close to the ground is drawn down to it [m].
constexpr double kSnapToGround = 0.3;
// A wall stands on the ground when its lowest cell above the foot band starts within this many
// support cells of the band (one cell, plus half of one for the cell's own extent).
constexpr double kStandingCells = 1.5;
// A ground triangle is drawn when at least this many of its three corners lie on cells the robot
// may use: a majority, so the drawn floor neither frays nor spills over red cells.
constexpr int kMinDrawnCorners = 2;
// Obstacle voxels are keyed by three signed 21-bit cell indices in one 64-bit word: +-2^20 cubes
// of kCubeSize (+-100 km) per axis, far beyond any map.
constexpr int kVoxelKeyBits = 21;
constexpr std::uint64_t kVoxelKeyMask = (std::uint64_t{1} << kVoxelKeyBits) - 1;

bool drawnAsGround(CellLabel label) {
  return robotFits(label);
}

// The drivable ground: the mesh's triangles at least two of whose corners lie on cells the robot
// may use, with the vertices they use (numbered as the triangles first use them). Counted before
// they are stored: a dense scan draws millions, and buffers grown by doubling would hold up to
// twice that at the run's memory peak.
void addGround(const Scan& scan, const ScanAnalysis& analysis, const TraversabilityMap& map,
               SceneGeometry& scene) {
  const GroundMesh& mesh = analysis.inputs.ground_mesh;
  std::vector<std::uint8_t> vertex_label(mesh.points.size());
  for (std::size_t v = 0; v < mesh.points.size(); ++v)
    vertex_label[v] = mesh.cells[v] == GroundMesh::kOutsideGrid ? std::uint8_t(CellLabel::kUnknown)
                                                                : map.labels[mesh.cells[v]];
  auto drawn = [&](const std::array<std::uint32_t, 3>& triangle) {
    int corners = 0;
    for (const std::uint32_t v : triangle)
      corners += int(drawnAsGround(CellLabel(vertex_label[v])));
    return corners >= kMinDrawnCorners;
  };
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> drawn_vertex(mesh.points.size(), kNone);
  std::uint32_t vertices = 0;
  std::size_t triangles = 0;
  for (const auto& triangle : mesh.triangles) {
    if (!drawn(triangle)) continue;
    ++triangles;
    for (const std::uint32_t v : triangle)
      if (drawn_vertex[v] == kNone) drawn_vertex[v] = vertices++;
  }
  scene.vertices.resize(vertices);
  scene.vertex_labels.resize(vertices);
  for (std::size_t v = 0; v < mesh.points.size(); ++v) {
    if (drawn_vertex[v] == kNone) continue;
    const Point3f& p = scan.points[mesh.points[v]];
    scene.vertices[drawn_vertex[v]] = Eigen::Vector3f(p.x, p.y, p.z);
    scene.vertex_labels[drawn_vertex[v]] = CellLabel(vertex_label[v]);
  }
  scene.triangles.reserve(triangles);
  for (const auto& triangle : mesh.triangles)
    if (drawn(triangle))
      scene.triangles.push_back(
          {drawn_vertex[triangle[0]], drawn_vertex[triangle[1]], drawn_vertex[triangle[2]]});
}

// Walls: upright boxes in the map frame (returned in the scanner's), one per run of a wall's
// supported cells.
std::vector<SceneBox> wallBoxes(const ScanAnalysis& analysis) {
  std::vector<SceneBox> walls;
  const Eigen::Isometry3d scanner_from_map = analysis.map_from_scanner.inverse();
  // Upright boxes in the map frame, aligned with the wall (its normal projected on the
  // ground), one per run of the wall's supported cells along it (so a door stays open), standing
  // on the ground and clipped below the lowest ceiling. The support image's own in-plane axes are
  // arbitrary, so they only serve to find the supported cells.
  const Eigen::Isometry3d& map_from_scanner = analysis.map_from_scanner;
  auto supportedCells = [&](std::size_t k, auto&& visit) {
    const Plane& plane = analysis.planes.planes[k];
    const SupportImage& image = analysis.planes.supports[k];
    for (int r = 0; r < image.height; ++r)
      for (int c = 0; c < image.width; ++c)
        if (image.kept[std::size_t(r) * std::size_t(image.width) + std::size_t(c)])
          visit(map_from_scanner *
                (plane.normal * plane.offset + image.u_axis * (image.u0 + (c + 0.5) * image.cell) +
                 image.v_axis * (image.v0 + (r + 0.5) * image.cell)));
  };
  double ceiling_height = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < analysis.planes.planes.size(); ++k) {
    if (analysis.planes.planes[k].kind != PlaneKind::kCeiling) continue;
    double sum = 0.0;
    std::size_t count = 0;
    supportedCells(k, [&](const Eigen::Vector3d& p) {
      sum += p.z();
      ++count;
    });
    if (count > 0 && sum / double(count) > kMinWallHeight)
      ceiling_height = std::min(ceiling_height, sum / double(count));
  }
  for (std::size_t k = 0; k < analysis.planes.planes.size(); ++k) {
    const Plane& plane = analysis.planes.planes[k];
    if (plane.kind != PlaneKind::kWall) continue;
    const Eigen::Vector3d normal = map_from_scanner.linear() * plane.normal;
    const Eigen::Vector3d across = Eigen::Vector3d(normal.x(), normal.y(), 0.0);
    if (across.norm() < kMinHorizontalNormal) continue;  // not a wall in the map frame
    const Eigen::Vector3d out = across.normalized();
    const Eigen::Vector3d along(-out.y(), out.x(), 0.0);
    // The wall's supported cells in bins along it: each bin's lowest and highest cell. Runs of
    // bins become boxes; an empty bin (a door, a gap) or a change between standing on the ground
    // and hanging (a lintel over a door) starts a new box.
    const double cell = analysis.planes.supports[k].cell;
    double depth = 0.0, a_min = std::numeric_limits<double>::infinity();
    std::vector<std::pair<double, Eigen::Vector3d>> cells;  // position along, map position
    supportedCells(k, [&](const Eigen::Vector3d& p) {
      cells.emplace_back(p.dot(along), p);
      a_min = std::min(a_min, p.dot(along));
      depth += p.dot(out);
    });
    if (cells.empty()) continue;
    depth /= double(cells.size());
    struct Bin {
      double low = std::numeric_limits<double>::infinity(), high = -low;
    };
    std::vector<Bin> bins;
    for (const auto& [a, p] : cells) {
      const auto index = std::size_t((a - a_min) / cell);
      if (index >= bins.size()) bins.resize(index + 1);
      // Cells at the foot are where the floor crosses the wall's plane, in a doorway too: they
      // say nothing about whether the wall is there.
      if (p.z() - cell / 2 < kSnapToGround) continue;
      bins[index].low = std::min(bins[index].low, p.z() - cell / 2);
      bins[index].high = std::max(bins[index].high, p.z() + cell / 2);
    }
    // Standing: the wall's cells begin right above the foot band.
    auto standing = [cell](const Bin& bin) {
      return bin.low < kSnapToGround + kStandingCells * cell;
    };
    Eigen::Matrix3d axes_in_map;
    axes_in_map << along, out, Eigen::Vector3d::UnitZ();
    for (std::size_t first = 0; first < bins.size();) {
      if (bins[first].high < bins[first].low) {  // empty
        ++first;
        continue;
      }
      std::size_t last = first;
      double bottom = bins[first].low, top = bins[first].high;
      while (last + 1 < bins.size() && bins[last + 1].high >= bins[last + 1].low &&
             standing(bins[last + 1]) == standing(bins[first])) {
        ++last;
        bottom = std::min(bottom, bins[last].low);
        top = std::max(top, bins[last].high);
      }
      // A wall seen down to near the ground stands on it (the lowest returns are often
      // shadowed); one that starts high (a lintel, a shelf's back) keeps its own bottom.
      if (standing(bins[first])) bottom = 0.0;
      top = std::min(top, ceiling_height - kCeilingClearance);
      const double a0 = a_min + double(first) * cell - cell / 2,
                   a1 = a_min + double(last + 1) * cell - cell / 2;
      first = last + 1;
      if (top - bottom <= kMinWallHeight) continue;
      const Eigen::Vector3d centre_in_map =
          along * (a0 + a1) / 2 + out * depth + Eigen::Vector3d(0, 0, (top + bottom) / 2);
      SceneBox box;
      box.center = (scanner_from_map * centre_in_map).cast<float>();
      box.axes = (scanner_from_map.linear() * axes_in_map).cast<float>();
      box.half_size =
          Eigen::Vector3f(float((a1 - a0) / 2), kWallHalfThickness, float((top - bottom) / 2));
      walls.push_back(box);
    }
  }

  return walls;
}

// Obstacles: cubes of the points between the ground and the robot's top.
std::vector<SceneBox> obstacleCubes(const ScanAnalysis& analysis, const TraversabilityMap& map,
                                    const RobotParams& robot) {
  std::vector<SceneBox> cubes;
  const Eigen::Isometry3d scanner_from_map = analysis.map_from_scanner.inverse();
  // One cube per occupied voxel of points between the ground and the robot's top.
  std::unordered_set<std::uint64_t> voxels;
  const Eigen::Matrix3f axes = scanner_from_map.linear().cast<float>();
  // A flight the map shows as stairs the robot can climb is drawn so here too, not as the red
  // cubes of an obstacle it cannot pass (its treads stand higher than the robot's step): the 3D
  // view drew the flight red where the map said "stairs, with care".
  auto onAClimbableFlight = [&](const MapObstacle& o) {
    const int flight = analysis.stairs.staircaseAt(o.cell);
    return flight >= 0 && o.cell < map.labels.size() &&
           CellLabel(map.labels[o.cell]) == CellLabel::kStairs &&
           analysis.stairs.staircases[std::size_t(flight)].containsPoint(
               Eigen::Vector3d(o.x, o.y, o.z));
  };
  for (const MapObstacle& o : analysis.inputs.obstacles) {
    if (o.height <= 0.0F || o.height >= robot.height || cubes.size() >= kMaxCubes) continue;
    const auto ix = std::int64_t(std::floor(o.x / kCubeSize)),
               iy = std::int64_t(std::floor(o.y / kCubeSize)),
               iz = std::int64_t(std::floor(o.z / kCubeSize));
    const std::uint64_t key = ((std::uint64_t(ix) & kVoxelKeyMask) << (2 * kVoxelKeyBits)) |
                              ((std::uint64_t(iy) & kVoxelKeyMask) << kVoxelKeyBits) |
                              (std::uint64_t(iz) & kVoxelKeyMask);
    if (!voxels.insert(key).second) continue;
    SceneBox cube;
    const Eigen::Vector3d centre((double(ix) + 0.5) * kCubeSize, (double(iy) + 0.5) * kCubeSize,
                                 (double(iz) + 0.5) * kCubeSize);
    cube.center = (scanner_from_map * centre).cast<float>();
    cube.axes = axes;
    cube.half_size = Eigen::Vector3f::Constant(kCubeSize / 2);
    cube.label = o.height <= robot.max_step ? CellLabel::kObstacle
                 : onAClimbableFlight(o)    ? CellLabel::kStairs
                                            : CellLabel::kImpassable;
    cubes.push_back(cube);
  }
  return cubes;
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
                                 const TraversabilityMap& map, const RobotParams& robot,
                                 int threads) {
  SceneGeometry scene;
  if (!analysis.ground_found) return scene;  // nothing drawn that cannot be trusted
  // The three parts share nothing: side by side.
  detail::parallelTasks(
      {[&] { addGround(scan, analysis, map, scene); }, [&] { scene.walls = wallBoxes(analysis); },
       [&] { scene.obstacles = obstacleCubes(analysis, map, robot); }},
      threads);
  return scene;
}

}  // namespace clearway
