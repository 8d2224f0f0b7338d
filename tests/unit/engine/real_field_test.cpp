// Real scans Clearway was not tuned on (docs/ALGORITHM.md, "Real scans from the field"): KITTI
// Velodyne frames (rings recovered from the azimuth wrap, the road classed ground) and the Hannover
// campus scans (open floor shown green or orange, nothing green where something stands), each
// measured by an oracle of its own that does not use the pipeline.

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <numbers>
#include <random>
#include <unordered_map>
#include <unordered_set>

#include "clearway/io/scan_io.h"
#include "clearway/pipeline.h"
#include "clearway/sensor_geometry.h"
#include "engine_fixtures.h"
#include "test_support.h"

namespace clearway {
namespace {

Eigen::Vector3d pointAt(const Scan& scan, std::size_t i) {
  const Point3f& p = scan.points[i];
  return {p.x, p.y, p.z};
}

long long packKey(int x, int y) {
  return (static_cast<long long>(x) << 32) ^ static_cast<long long>(static_cast<std::uint32_t>(y));
}

// ---- KITTI: the road surface fitted by RANSAC on points near the sensor's expected height ----

struct RoadPlane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // pointing up
  double offset = 0.0;                                // n . p = offset on the road
  double height(const Eigen::Vector3d& p) const { return normal.dot(p) - offset; }
};

// The HDL-64E sits about 1.73 m above the road (KITTI): road candidates lie 1.2-2.3 m below it,
// within 30 m. RANSAC (fixed seed) keeps the plane with most points within 0.1 m and no steeper
// than 10 deg, then refits it to those points by least squares.
RoadPlane fitRoad(const Scan& scan) {
  std::vector<Eigen::Vector3d> candidates;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!scan.isValid(i)) continue;
    const Eigen::Vector3d p = pointAt(scan, i);
    if (p.z() < -2.3 || p.z() > -1.2 || p.head<2>().norm() > 30.0) continue;
    candidates.push_back(p);
  }
  std::mt19937 random(14);
  std::uniform_int_distribution<std::size_t> pick(0, candidates.size() - 1);
  RoadPlane best;
  std::size_t best_count = 0;
  for (int iteration = 0; iteration < 400; ++iteration) {
    const Eigen::Vector3d a = candidates[pick(random)], b = candidates[pick(random)],
                          c = candidates[pick(random)];
    Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-6) continue;
    n.normalize();
    if (n.z() < 0) n = -n;
    if (n.z() < std::cos(10.0 * std::numbers::pi / 180.0)) continue;
    const RoadPlane plane{n, n.dot(a)};
    std::size_t count = 0;
    for (const Eigen::Vector3d& p : candidates)
      count += std::abs(plane.height(p)) < 0.1;
    if (count > best_count) {
      best_count = count;
      best = plane;
    }
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> inliers;
  for (const Eigen::Vector3d& p : candidates)
    if (std::abs(best.height(p)) < 0.1) inliers.push_back(p);
  for (const Eigen::Vector3d& p : inliers)
    mean += p;
  mean /= double(inliers.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : inliers)
    covariance += (p - mean) * (p - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  Eigen::Vector3d n = solver.eigenvectors().col(0);
  if (n.z() < 0) n = -n;
  return {n, n.dot(mean)};
}

class KittiFrame : public ::testing::TestWithParam<const char*> {};

TEST_P(KittiFrame, RingsAreRecovered) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, std::string("kitti/") + GetParam());
  const Scan scan = loadScan(file);
  // KITTI keeps 64 rings one after another; each ends where the azimuth has gone once around.
  EXPECT_EQ(scan.lines.size(), 64u);
  const SensorGeometry sensor = describeSensor(scan);
  EXPECT_EQ(sensor.kind, SensorKind::kMultiBeam);
  EXPECT_NEAR(sensor.between_line_step * 180.0 / std::numbers::pi, 0.4, 0.1);
  EXPECT_FALSE(sensor.closed_turn);
}

// What the pipeline classes ground, measured against the oracle's road: points within 0.15 m of
// it, and points more than 0.5 m above it.
struct RoadFigures {
  std::size_t on_road = 0, on_road_ground = 0, high = 0, high_ground = 0;
  double recall() const {
    return double(on_road_ground) / double(std::max<std::size_t>(on_road, 1));
  }
  double falseRate() const { return double(high_ground) / double(std::max<std::size_t>(high, 1)); }
};

RoadFigures measureRoad(const Scan& scan, const PipelineResult& result, const RoadPlane& road) {
  RoadFigures figures;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!scan.isValid(i)) continue;
    const double height = road.height(pointAt(scan, i));
    const bool ground = result.point_classes[i] == PointClass::kGround;
    if (std::abs(height) <= 0.15) {
      ++figures.on_road;
      figures.on_road_ground += ground;
    } else if (height > 0.5) {
      ++figures.high;
      figures.high_ground += ground;
    }
  }
  std::cout << "[ figures  ] " << figures.on_road_ground << " of " << figures.on_road
            << " road points ground (" << figures.recall() << "), " << figures.high_ground << " of "
            << figures.high << " points > 0.5 m above the road ground (" << figures.falseRate()
            << ")\n";
  return figures;
}

// The road is ground: the frame's own pose (KITTI: z up), planes validated by their crowding about
// the local surface, road patches absorbed into the road, ground kept where the robot can drive
// onto it (docs/ALGORITHM.md, "Multi-beam frames").
TEST_P(KittiFrame, TheRoadIsGround) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, std::string("kitti/") + GetParam());
  const Scan scan = loadScan(file);

  const PipelineResult result = runPipeline(scan, SegmentationParams{});
  ASSERT_TRUE(result.trusted()) << result.reason;

  const RoadPlane road = fitRoad(scan);
  // The oracle itself: about 1.73 m below the sensor.
  EXPECT_NEAR(road.offset, -1.73, 0.15);
  // The reference ground is the road: parallel to it within 1 deg, at its height within 5 cm.
  const Plane& reference =
      result.analysis->planes.planes[std::size_t(result.analysis->reference_ground)];
  EXPECT_GT(std::abs(reference.normal.dot(road.normal)), std::cos(1.0 * std::numbers::pi / 180.0));
  EXPECT_NEAR(reference.offset, -road.offset, 0.05);
  EXPECT_GE(measureRoad(scan, result, road).recall(), 0.80);
  // The rings never see the ground around the car: the robot's reach is its own island, and the
  // map says why rather than leaving a reach of a few cells unexplained.
  EXPECT_NE(result.map.reach_limit.find("not seen"), std::string::npos) << result.map.reach_limit;
  // It fits a few centimetres from its own place, in another heading: it cannot turn there, and
  // the words say so rather than "the nearest such cell is 0.0 m away".
  EXPECT_NE(result.map.reach_limit.find("fits right beside its own place"), std::string::npos)
      << result.map.reach_limit;
  EXPECT_EQ(result.map.reach_limit.find("0.0 m"), std::string::npos) << result.map.reach_limit;
}

// The frame's returns that `keep` (ring, point) accepts, ring by ring: a sparser head, a crop.
template <typename Keep>
Scan subsetOf(const Scan& scan, Keep&& keep) {
  Scan subset;
  subset.sensor_pose = scan.sensor_pose;
  subset.pose_source = scan.pose_source;
  for (std::size_t ring = 0; ring < scan.lines.size(); ++ring) {
    ScanLine line;
    line.first = subset.points.size();
    const ScanLine& whole = scan.lines[ring];
    for (std::size_t i = whole.first; i < whole.first + whole.count; ++i) {
      if (!keep(ring, scan.points[i])) continue;
      subset.points.push_back(scan.points[i]);
      subset.status.push_back(scan.status[i]);
    }
    line.count = subset.points.size() - line.first;
    if (line.count > 0) subset.lines.push_back(line);
  }
  return subset;
}

// A sparser head's frame: every fourth ring of the HDL-64E's, 1.6 deg apart as a VLP-16's 2 deg
// nearly are. Each ring is a thin arc on a plane's support image, and only the cells between
// facing rings make the road an area (src/segmentation/ring_support.h): without them there was
// no supported area at all ("0.00 m2"), and with every third ring the road was 94 % obstacle.
TEST_P(KittiFrame, TheRoadIsGroundForASparserHead) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, std::string("kitti/") + GetParam());
  const Scan frame = loadScan(file);
  const RoadPlane road = fitRoad(frame);
  for (const std::size_t every : {3, 4}) {
    const Scan sparser =
        subsetOf(frame, [every](std::size_t ring, const Point3f&) { return ring % every == 0; });
    EXPECT_EQ(describeSensor(sparser).kind, SensorKind::kMultiBeam);
    const PipelineResult result = runPipeline(sparser, SegmentationParams{});
    ASSERT_TRUE(result.trusted()) << "every " << every << ": " << result.analysis->reason;
    const RoadFigures figures = measureRoad(sparser, result, road);
    EXPECT_GE(figures.recall(), 0.80) << "every " << every << " rings";
    EXPECT_LT(figures.falseRate(), 0.01) << "every " << every << " rings";
  }
}

// A frame cropped to the camera's view (common with KITTI) sweeps a quarter turn per ring: still
// rings, each a cone of one elevation, not the fans of a rotating 2D scanner.
TEST_P(KittiFrame, AFrameCroppedToTheCamerasViewIsStillMultiBeam) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, std::string("kitti/") + GetParam());
  const Scan frame = loadScan(file);
  const RoadPlane road = fitRoad(frame);
  constexpr double kHalfView = 45.0 * std::numbers::pi / 180.0;
  const Scan cropped = subsetOf(frame, [](std::size_t, const Point3f& p) {
    return p.x > 0.0F && std::abs(std::atan2(p.y, p.x)) <= kHalfView;
  });
  const SensorGeometry sensor = describeSensor(cropped);
  EXPECT_EQ(sensor.kind, SensorKind::kMultiBeam);
  EXPECT_NEAR(sensor.between_line_step * 180.0 / std::numbers::pi, 0.4, 0.1);
  const PipelineResult result = runPipeline(cropped, SegmentationParams{});
  ASSERT_TRUE(result.trusted()) << result.analysis->reason;
  EXPECT_GE(measureRoad(cropped, result, road).recall(), 0.80);
}

// Car roofs and bonnets are flat and below the sensor, and planes fitted to a few rings cross the
// road at an angle: neither may make what stands on the road ground.
TEST_P(KittiFrame, LittleAboveTheRoadIsGround) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, std::string("kitti/") + GetParam());
  const Scan scan = loadScan(file);
  const PipelineResult result = runPipeline(scan, SegmentationParams{});
  ASSERT_TRUE(result.trusted()) << result.analysis->reason;
  EXPECT_LT(measureRoad(scan, result, fitRoad(scan)).falseRate(), 0.01);
}

// The same frame tilted a little, as a car braking or standing on a slope tilts its sensor against
// the road: the frame's pose still says "z up", the planes are fitted afresh. On 000002 tilted
// 1 deg nose down, a plane fitted along the foot of a hedge climbed to its top and carried it into
// the ground: 5.3 % of what stands 0.5 m above the road was ground, 1,803 points on the hedge's
// top 1 m up (now 0.6 %: ground lies on top of its column, see dropGroundOverLowerReturns).
TEST_P(KittiFrame, LittleAboveTheRoadIsGroundWhenTheFrameIsTilted) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, std::string("kitti/") + GetParam());
  const Scan frame = loadScan(file);
  const RoadPlane level_road = fitRoad(frame);
  for (const auto& [axis, degrees] :
       std::vector<std::pair<Eigen::Vector3d, double>>{{Eigen::Vector3d::UnitY(), -3.0},
                                                       {Eigen::Vector3d::UnitY(), -1.0},
                                                       {Eigen::Vector3d::UnitY(), 2.0},
                                                       {Eigen::Vector3d::UnitX(), -2.0},
                                                       {Eigen::Vector3d::UnitX(), 1.0},
                                                       {Eigen::Vector3d::UnitX(), 3.0}}) {
    SCOPED_TRACE(::testing::Message() << degrees << " deg about " << axis.transpose());
    const Eigen::Matrix3d turn =
        Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, axis).toRotationMatrix();
    Scan tilted = frame;
    for (Point3f& p : tilted.points) {
      const Eigen::Vector3d q = turn * Eigen::Vector3d(p.x, p.y, p.z);
      p = {float(q.x()), float(q.y()), float(q.z())};
    }
    // The road turns with the frame about the sensor: its offset is kept.
    const RoadPlane road{turn * level_road.normal, level_road.offset};
    const PipelineResult result = runPipeline(tilted, SegmentationParams{});
    ASSERT_TRUE(result.trusted()) << result.analysis->reason;
    const RoadFigures figures = measureRoad(tilted, result, road);
    EXPECT_GE(figures.recall(), 0.80);
    EXPECT_LT(figures.falseRate(), 0.01);
  }
}

// The map of a multi-beam frame stops where its rings can no longer vouch for the ground (plus the
// robot's circumscribed radius), not at map.max_extent: beyond it no cell could be green.
TEST_P(KittiFrame, TheMapStopsWhereTheRingsVouchForTheGround) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, std::string("kitti/") + GetParam());
  const Scan scan = loadScan(file);
  const SegmentationParams params;
  const PipelineResult result = runPipeline(scan, params);
  ASSERT_TRUE(result.trusted()) << result.analysis->reason;
  const double height = result.analysis->map_from_scanner.translation().z();
  const double largest_hidden = 2 * params.robot.max_step;  // cell_classes.h, kSpacingPerStep
  const double range =
      vouchedRange(result.analysis->sensor, height, largest_hidden, params.map.max_extent);
  // The vouched range is where the hidden-obstacle bound crosses twice the step: the HDL-64E's
  // 0.41 deg ring step gives about 14 m.
  auto hidden = [&](double r) {
    return hiddenObstacleSize(result.analysis->sensor, Eigen::Vector3d(r, 0.0, -height),
                              Eigen::Vector3d::UnitZ(), height);
  };
  EXPECT_LE(hidden(range), largest_hidden);
  EXPECT_GT(hidden(range + 0.2), largest_hidden);
  EXPECT_LT(range, params.map.max_extent / 2);
  const MapGrid& grid = result.map.grid;
  const double reach = range + std::hypot(params.robot.width, params.robot.length) / 2 + 0.25 +
                       2 * grid.resolution;  // the map's rim and rounding
  EXPECT_GE(grid.origin.x(), -reach);
  EXPECT_GE(grid.origin.y(), -reach);
  EXPECT_LE(grid.origin.x() + grid.width * grid.resolution, reach);
  EXPECT_LE(grid.origin.y() + grid.height * grid.resolution, reach);
  std::cout << "[ figures  ] vouched range " << range << " m, map " << grid.width << " x "
            << grid.height << " cells\n";
}

// `info` names the sensor and its rings.
// A frame's rings may be stored top down (KITTI) or bottom up (a ROS driver's ring field): the map
// must not depend on it much. The ground triangles between two rings took the length limit of
// the ring they were paired from, so bottom up they kept less of the road: 000002 showed 81,330
// traversable cells against 86,289 as stored (now 85,635). What is left comes from the plane
// clustering, which grows planes from each line to the lines after it (000001: 58 planes as
// stored, 70 bottom up).
TEST_P(KittiFrame, TheMapHardlyDependsOnWhichWayItsRingsAreStored) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, std::string("kitti/") + GetParam());
  const Scan frame = loadScan(file);
  const Scan bottom_up = test::linesReversed(frame);
  auto traversable = [](const PipelineResult& result) {
    return double(result.map.counts[std::size_t(CellLabel::kTraversable)]);
  };
  const PipelineResult stored = runPipeline(frame, SegmentationParams{});
  const PipelineResult reversed = runPipeline(bottom_up, SegmentationParams{});
  ASSERT_TRUE(stored.trusted()) << stored.reason;
  ASSERT_TRUE(reversed.trusted()) << reversed.reason;
  std::cout << "[ figures  ] " << GetParam() << ": " << traversable(stored)
            << " traversable cells as stored, " << traversable(reversed) << " bottom up\n";
  EXPECT_NEAR(traversable(reversed), traversable(stored), 0.05 * traversable(stored));
}

TEST_P(KittiFrame, InfoSaysMultiBeamAndItsRings) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, std::string("kitti/") + GetParam());
  const test::CommandResult info = test::runCli("info " + test::shellQuote(file.string()));
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_NE(info.out.find("multi-beam, rings: 64"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("pose source: file (kitti bin)"), std::string::npos) << info.out;
}

INSTANTIATE_TEST_SUITE_P(Kitti, KittiFrame, ::testing::Values("000001.bin", "000002.bin"));

// ---- Hannover: open floor against what the map shows ----

// The oracle's local ground: per 0.5 m tile, the lowest point within 0.75 m (a window of three
// tiles), so walls and trees do not raise it and a gentle slope lowers it by a few centimetres.
class LocalGround {
 public:
  explicit LocalGround(const Scan& scan) {
    for (std::size_t i = 0; i < scan.size(); ++i)
      if (scan.isValid(i)) {
        const Eigen::Vector3d p = pointAt(scan, i);
        const auto key = tileOf(p.x(), p.y());
        auto [it, inserted] = lowest_.emplace(key, p.z());
        if (!inserted) it->second = std::min(it->second, p.z());
      }
  }
  // NaN where nothing was seen nearby.
  double at(double x, double y) const {
    const auto [tx, ty] = tileOf(x, y);
    double lowest = std::numeric_limits<double>::quiet_NaN();
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const auto it = lowest_.find({tx + dx, ty + dy});
        if (it != lowest_.end() && !(it->second >= lowest)) lowest = it->second;
      }
    return lowest;
  }

 private:
  static constexpr double kTile = 0.5;
  struct KeyHash {
    std::size_t operator()(const std::pair<int, int>& k) const {
      return std::hash<long long>()(packKey(k.first, k.second));
    }
  };
  static std::pair<int, int> tileOf(double x, double y) {
    return {int(std::floor(x / kTile)), int(std::floor(y / kTile))};
  }
  std::unordered_map<std::pair<int, int>, double, KeyHash> lowest_;
};

struct OpenFloorFigures {
  std::size_t open_positions = 0;  // robot-sized open floor, on a 0.1 m lattice
  std::size_t shown = 0;           // of those, green or orange on the map
  std::size_t green_over_obstacle = 0;
};

// Open floor: positions whose disk of the robot's circumscribed radius has a floor return (within
// 0.1 m of the local ground) in every 0.3 m square whose centre lies in it, and no point between
// 0.1 m and the robot's height above the local ground. Measured in the scan frame (z up: the
// Hannover poses only turn about the vertical).
// With `within_map`, only positions on the map's grid count (a multi-beam frame's map stops where
// its rings vouch for the ground, 14 m out, and the frame reaches 80 m).
OpenFloorFigures measureOpenFloor(const Scan& scan, const PipelineResult& result,
                                  bool within_map = false) {
  const RobotParams robot;
  const double radius = std::hypot(robot.width, robot.length) / 2;
  const LocalGround ground(scan);
  constexpr double kFloorSquare = 0.3, kObstacleSquare = 0.1;
  std::unordered_set<long long> floor, obstacle;
  auto key = [](double x, double y, double size) {
    return packKey(int(std::floor(x / size)), int(std::floor(y / size)));
  };
  std::vector<std::pair<Eigen::Vector3d, double>> high_points;  // with their height
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!scan.isValid(i)) continue;
    const Eigen::Vector3d p = pointAt(scan, i);
    const double g = ground.at(p.x(), p.y());
    const double height = p.z() - g;
    if (height <= 0.1) floor.insert(key(p.x(), p.y(), kFloorSquare));
    if (height > 0.1 && height < robot.height) obstacle.insert(key(p.x(), p.y(), kObstacleSquare));
    if (height > 0.3 && height < 1.5) high_points.emplace_back(p, height);
  }

  const TraversabilityMap& map = result.map;
  const Eigen::Isometry3d map_from_scanner = result.analysis->map_from_scanner;
  auto labelAt = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d m = map_from_scanner * p;
    const Eigen::Vector2i cell = map.grid.cellOf(m.x(), m.y());
    if (!map.grid.inside(cell.x(), cell.y())) return CellLabel::kUnknown;
    return map.label(cell.x(), cell.y());
  };

  OpenFloorFigures figures;
  Bounds bounds = validBounds(scan);
  if (within_map) {
    // The grid's corners in the scan frame (the map frame only turns about the vertical here).
    const Eigen::Isometry3d scanner_from_map = map_from_scanner.inverse();
    Eigen::AlignedBox2d box;
    for (const double fx : {0.0, 1.0})
      for (const double fy : {0.0, 1.0}) {
        const Eigen::Vector2d corner =
            map.grid.origin +
            map.grid.resolution * Eigen::Vector2d(fx * map.grid.width, fy * map.grid.height);
        box.extend((scanner_from_map * Eigen::Vector3d(corner.x(), corner.y(), 0.0)).head<2>());
      }
    bounds.min.x = float(std::max(double(bounds.min.x), box.min().x()));
    bounds.min.y = float(std::max(double(bounds.min.y), box.min().y()));
    bounds.max.x = float(std::min(double(bounds.max.x), box.max().x()));
    bounds.max.y = float(std::min(double(bounds.max.y), box.max().y()));
  }
  const int floor_reach = int(std::ceil(radius / kFloorSquare)) + 1;
  const int obstacle_reach = int(std::ceil(radius / kObstacleSquare)) + 1;
  for (double y = bounds.min.y; y <= bounds.max.y; y += 0.1)
    for (double x = bounds.min.x; x <= bounds.max.x; x += 0.1) {
      bool open = true;
      const int fx = int(std::floor(x / kFloorSquare)), fy = int(std::floor(y / kFloorSquare));
      for (int dy = -floor_reach; dy <= floor_reach && open; ++dy)
        for (int dx = -floor_reach; dx <= floor_reach && open; ++dx) {
          const double cx = (fx + dx + 0.5) * kFloorSquare, cy = (fy + dy + 0.5) * kFloorSquare;
          if (std::hypot(cx - x, cy - y) > radius) continue;
          open = floor.count(packKey(fx + dx, fy + dy)) > 0;
        }
      const int ox = int(std::floor(x / kObstacleSquare)),
                oy = int(std::floor(y / kObstacleSquare));
      for (int dy = -obstacle_reach; dy <= obstacle_reach && open; ++dy)
        for (int dx = -obstacle_reach; dx <= obstacle_reach && open; ++dx) {
          const double cx = (ox + dx + 0.5) * kObstacleSquare,
                       cy = (oy + dy + 0.5) * kObstacleSquare;
          if (std::hypot(cx - x, cy - y) > radius + kObstacleSquare) continue;
          open = obstacle.count(packKey(ox + dx, oy + dy)) == 0;
        }
      if (!open) continue;
      ++figures.open_positions;
      const double g = ground.at(x, y);
      const CellLabel label = labelAt({x, y, std::isnan(g) ? 0.0 : g});
      figures.shown += label == CellLabel::kTraversable || label == CellLabel::kCareful ||
                       label == CellLabel::kObstacle;
    }

  std::unordered_set<std::size_t> green_cells;
  for (const auto& [p, height] : high_points) {
    const Eigen::Vector3d m = map_from_scanner * p;
    const Eigen::Vector2i cell = map.grid.cellOf(m.x(), m.y());
    if (!map.grid.inside(cell.x(), cell.y())) continue;
    if (map.label(cell.x(), cell.y()) == CellLabel::kTraversable)
      green_cells.insert(map.grid.index(cell.x(), cell.y()));
  }
  figures.green_over_obstacle = green_cells.size();
  return figures;
}

class HannoverScan : public ::testing::TestWithParam<const char*> {};

TEST_P(HannoverScan, OpenFloorIsShownAndNothingGreenStandsOnAnObstacle) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, std::string("hannover1/") + GetParam());
  const Scan scan = loadScan(file);
  const PipelineResult result = runPipeline(scan, SegmentationParams{});
  ASSERT_TRUE(result.trusted()) << result.reason;
  const OpenFloorFigures figures = measureOpenFloor(scan, result);
  const double shown =
      double(figures.shown) / double(std::max<std::size_t>(figures.open_positions, 1));
  std::cout << "[ figures  ] " << GetParam() << ": " << figures.shown << " of "
            << figures.open_positions << " open-floor positions shown green or orange (" << shown
            << "), " << figures.green_over_obstacle
            << " green cells with a point 0.3-1.5 m above the local ground\n";
  EXPECT_GT(figures.open_positions, 100u);
  // Issue 14 asks for 0.80 (1.0 and 0.953 since ground that no plane took in continues the
  // planes'; 0.998 and 0.905 since ground planes join across a kerb lower than the robot's step;
  // 0.915 and 0.905 once fans run together in the file, a fan passing over something near and a
  // turntable's second pass were triangulated as such; 0.70-0.74 before, and 0.30-0.33 at first).
  EXPECT_GE(shown, 0.80);
  EXPECT_EQ(figures.green_over_obstacle, 0u);
}

// Real scanners lose returns (dark or wet paving, puddles, dust): the same scans with a fifth of
// their returns lost at random, and with every second return of each line lost. The ground
// triangles bridge up to two lost returns in a row (core/src/segmentation/ground_triangles.h), and
// the density check counts the wider spacing there (0.82 and 0.63 of the open floor shown with a
// fifth lost, 0.92 and 0.98 with every second lost). When a triangle needed three returns, a fifth
// lost (another draw) showed 0.3 % and 0.03 % of it, every second lost none.
TEST_P(HannoverScan, ReturnsLostAtRandomLeaveTheFloorShown) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, std::string("hannover1/") + GetParam());
  const Scan scan = loadScan(file);
  Scan fifth_lost = scan, every_second_lost = scan;
  std::mt19937 random(5);
  std::bernoulli_distribution lost(0.2);
  for (std::size_t i = 0; i < scan.size(); ++i)
    if (scan.isValid(i) && lost(random)) fifth_lost.status[i] = PointStatus::kNoReturn;
  for (const ScanLine& line : scan.lines)
    for (std::size_t i = line.first + 1; i < line.first + line.count; i += 2)
      every_second_lost.status[i] = PointStatus::kNoReturn;
  for (const auto& [name, lossy] : {std::pair{"a fifth lost", &fifth_lost},
                                    std::pair{"every second lost", &every_second_lost}}) {
    const PipelineResult result = runPipeline(*lossy, SegmentationParams{});
    ASSERT_TRUE(result.trusted()) << name << ": " << result.reason;
    const OpenFloorFigures figures = measureOpenFloor(*lossy, result);
    const double shown =
        double(figures.shown) / double(std::max<std::size_t>(figures.open_positions, 1));
    std::cout << "[ figures  ] " << GetParam() << ", " << name << ": " << figures.shown << " of "
              << figures.open_positions << " open-floor positions shown (" << shown << "), "
              << figures.green_over_obstacle
              << " green cells with a point 0.3-1.5 m above the local ground\n";
    EXPECT_GE(shown, 0.5) << name;
    EXPECT_EQ(figures.green_over_obstacle, 0u) << name;
  }
}

INSTANTIATE_TEST_SUITE_P(Hannover, HannoverScan, ::testing::Values("scan100.3d", "scan440.3d"));

// The road's open floor is shown, as the Hannover scans' is: on KITTI's 000002.bin as stored
// (rings starting ahead, returns out of azimuth order) the map showed 18,128 traversable cells
// against 80,094 with the same rings sorted by azimuth, the rings paired no further than the first
// return out of order (0.41 and 0.50 of the open floor shown then, 0.86 and 0.95 since).
TEST_P(KittiFrame, OpenRoadIsShownAndNothingGreenStandsOnAnObstacle) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, std::string("kitti/") + GetParam());
  const Scan scan = loadScan(file);
  const PipelineResult result = runPipeline(scan, SegmentationParams{});
  ASSERT_TRUE(result.trusted()) << result.reason;
  const OpenFloorFigures figures = measureOpenFloor(scan, result, true);
  const double shown =
      double(figures.shown) / double(std::max<std::size_t>(figures.open_positions, 1));
  std::cout << "[ figures  ] " << GetParam() << ": " << figures.shown << " of "
            << figures.open_positions << " open-floor positions on the map shown green or orange ("
            << shown << "), " << figures.green_over_obstacle
            << " green cells with a point 0.3-1.5 m above the local ground\n";
  EXPECT_GT(figures.open_positions, 1000u);
  EXPECT_GE(shown, 0.80);
  EXPECT_EQ(figures.green_over_obstacle, 0u);
}

// A box that returns nothing (black, or glass) on the road ahead: a file of rings that keeps only
// the returns (KITTI's) shows it as a gap in each ring that meets it or passes over its shadow,
// 14 to 35 of the sensor's steps wide. The ground triangles bridged gaps narrower than their edge
// limit (1 m): a box 0.5 m square and 0.4 m high 8 m ahead was shown green, all 64 cells inside
// it. Nothing may be shown there, and the road around it still is.
struct ReturnlessBox {
  Eigen::Vector2d centre;
  double side, height;  // [m]
};

TEST_P(KittiFrame, AnObstacleThatReturnsNothingIsNotBridged) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, std::string("kitti/") + GetParam());
  const Scan frame = loadScan(file);
  const RoadPlane road = fitRoad(frame);
  for (const ReturnlessBox& box :
       {ReturnlessBox{{8.0, 0.0}, 0.5, 0.4}, ReturnlessBox{{10.0, 0.0}, 0.6, 0.5},
        ReturnlessBox{{8.0, 0.0}, 0.8, 1.0}}) {
    const double half_side = box.side / 2;
    // Whether the ray from the sensor to `p` meets the box (from 0.1 m under the road, where its
    // foot's returns would be, to its top).
    auto hidden = [&](const Point3f& point) {
      const Eigen::Vector3d p(point.x, point.y, point.z);
      constexpr int kSamples = 400;
      for (int k = 1; k <= kSamples; ++k) {
        const Eigen::Vector3d q = p * (double(k) / kSamples);
        const double height = road.height(q);
        if ((q.head<2>() - box.centre).cwiseAbs().maxCoeff() < half_side && height > -0.1 &&
            height < box.height)
          return true;
      }
      return false;
    };
    const Scan scan = subsetOf(frame, [&](std::size_t, const Point3f& p) { return !hidden(p); });
    ASSERT_LT(scan.size(), frame.size());
    const PipelineResult result = runPipeline(scan, SegmentationParams{});
    ASSERT_TRUE(result.trusted()) << result.reason;
    const TraversabilityMap& map = result.map;
    const Eigen::Isometry3d scanner_from_map = result.analysis->map_from_scanner.inverse();
    std::size_t inside = 0, shown = 0;
    for (int row = 0; row < map.grid.height; ++row)
      for (int column = 0; column < map.grid.width; ++column) {
        const Eigen::Vector2d m = map.grid.centre(column, row);
        const Eigen::Vector3d p = scanner_from_map * Eigen::Vector3d(m.x(), m.y(), 0.0);
        if ((p.head<2>() - box.centre).cwiseAbs().maxCoeff() >= half_side - map.grid.resolution)
          continue;
        ++inside;
        shown += map.label(column, row) != CellLabel::kUnknown;
      }
    const OpenFloorFigures figures = measureOpenFloor(scan, result, true);
    const double open_shown =
        double(figures.shown) / double(std::max<std::size_t>(figures.open_positions, 1));
    std::cout << "[ figures  ] " << GetParam() << ", box " << box.side << " m " << box.centre.x()
              << " m ahead: " << shown << " of the " << inside
              << " cells inside it on the map; open floor shown " << open_shown << "\n";
    EXPECT_GE(inside, 16u);
    EXPECT_EQ(shown, 0u) << "box " << box.side << " m";
    EXPECT_GE(open_shown, 0.80);
    EXPECT_EQ(figures.green_over_obstacle, 0u);
  }
}

// ---- A room: ground is the lowest surface in its column ----

// The PCL room's table top, 0.72 m above the floor, is flat, below the scanner and large: it was a
// ground plane (4,134 returns) although the floor is seen under it. Ground returns more than
// 0.5 m above the reference ground (the floor) must be few.
TEST(RoomScan, TheTableTopIsNotGround) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, "pcl-room/room_scan1.pcd");
  const Scan scan = loadScan(file);
  const PipelineResult result = runPipeline(scan, SegmentationParams{});
  ASSERT_TRUE(result.trusted()) << result.reason;
  std::size_t ground = 0, raised = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (result.point_classes[i] != PointClass::kGround) continue;
    ++ground;
    // The map frame's z is the height above the reference ground.
    raised += (result.analysis->map_from_scanner * pointAt(scan, i)).z() > 0.5;
  }
  std::cout << "[ figures  ] " << raised << " of " << ground
            << " ground returns more than 0.5 m above the floor\n";
  EXPECT_GT(ground, 5000u);
  EXPECT_LT(double(raised), 0.01 * double(ground));
}

// ---- The seam: where the turn starts does not change the map ----

// The same scan with its lines turned: line k becomes line (k + shift) mod n, so the turn starts
// and ends elsewhere.
Scan turnLines(const Scan& scan, std::size_t shift) {
  Scan turned = scan;
  turned.points.clear();
  turned.status.clear();
  turned.intensity.clear();
  turned.lines.clear();
  const std::size_t n = scan.lines.size();
  for (std::size_t k = 0; k < n; ++k) {
    const ScanLine& line = scan.lines[(k + shift) % n];
    turned.lines.push_back({turned.points.size(), line.count, line.beta});
    for (std::size_t i = line.first; i < line.first + line.count; ++i) {
      turned.points.push_back(scan.points[i]);
      turned.status.push_back(scan.status[i]);
      if (!scan.intensity.empty()) turned.intensity.push_back(scan.intensity[i]);
    }
  }
  return turned;
}

class Seam : public ::testing::TestWithParam<const char*> {};

TEST_P(Seam, TurningTheStartOfTheTurnKeepsTheMap) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, std::string("hannover1/") + GetParam());
  const Scan scan = loadScan(file);
  ASSERT_TRUE(describeSensor(scan).closed_turn);
  const PipelineResult original = runPipeline(scan, SegmentationParams{});
  ASSERT_TRUE(original.trusted());
  for (const std::size_t shift : {scan.lines.size() / 4, scan.lines.size() / 2}) {
    SCOPED_TRACE(shift);
    const Scan turned = turnLines(scan, shift);
    ASSERT_TRUE(describeSensor(turned).closed_turn);
    const PipelineResult result = runPipeline(turned, SegmentationParams{});
    ASSERT_TRUE(result.trusted());
    auto shown = [](const TraversabilityMap& map) {
      return double(map.counts[1] + map.counts[2] + map.counts[3]);
    };
    std::cout << "[ figures  ] " << GetParam() << " turned by " << shift
              << " lines: " << shown(result.map) << " green/orange cells against "
              << shown(original.map) << ", red " << result.map.counts[4] << " against "
              << original.map.counts[4] << "\n";
    EXPECT_NEAR(shown(result.map), shown(original.map), 0.02 * shown(original.map));
    EXPECT_NEAR(double(result.map.counts[4]), double(original.map.counts[4]),
                0.02 * double(original.map.counts[4]));
  }
  // Half of the turn is not a full turn: its ends are not neighbours.
  Scan half = scan;
  half.lines.resize(scan.lines.size() / 2);
  const std::size_t kept = half.lines.back().first + half.lines.back().count;
  half.points.resize(kept);
  half.status.resize(kept);
  if (!half.intensity.empty()) half.intensity.resize(kept);
  EXPECT_FALSE(describeSensor(half).closed_turn);
}

INSTANTIATE_TEST_SUITE_P(Hannover, Seam, ::testing::Values("scan100.3d", "scan440.3d"));

}  // namespace
}  // namespace clearway
