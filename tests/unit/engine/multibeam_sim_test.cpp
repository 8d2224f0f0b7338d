// A multi-beam frame of a simulated street with known geometry (docs/ALGORITHM.md, "Multi-beam
// frames"): the rings of a head 1.73 m above a road (an HDL-64E's 64 rings 0.42 deg apart, an
// HDL-32E's 32 rings 1.33 deg apart, a VLP-16's 16 rings 2 deg apart), a pavement behind a kerb
// lower than the robot's step, a parked car and a facade, ray-cast by our own simulator. The road
// and the pavement are ground; the car's roof and bonnet, flat and below the sensor, are not.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "clearway/io/scan_io.h"
#include "clearway/pipeline.h"
#include "clearway/sensor_geometry.h"
#include "clearway/sim/ray_caster.h"
#include "clearway/sim/scene.h"
#include "engine_fixtures.h"
#include "test_support.h"

namespace clearway {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kSensorHeight = 1.73;  // [m], as KITTI's
constexpr int kAzimuths = 1800;         // 0.2 deg apart
constexpr double kMaxRange = 80.0;      // [m]
constexpr double kRangeNoise = 0.01;    // [m], one sigma
constexpr double kKerb = 0.08;          // [m], lower than the robot's 0.1 m step

// A multi-beam head: its rings from the top elevation down, evenly apart [deg], and what it must
// show: the share of road points classed ground, and how close the reference ground comes to the
// road's height [m].
struct Head {
  const char* name;
  int rings;
  double top_elevation, ring_step;
  double road_share, height_tolerance;
};

const Head kHeads[] = {
    {"HDL64E", 64, 2.0, 0.42, 0.9, 0.02},     // down to -24.5 deg
    {"HDL32E", 32, 10.67, 1.333, 0.9, 0.02},  // down to -30.7 deg
    // Down to -15 deg: the road from 6.5 m on, its rings beyond 11 m more than 3 m apart (over
    // the 2 m a plane's area spans between rings), each on its own: no plane is clustered from
    // them and the plane rests on fewer rings. Ground followed outward ring by ring
    // (segmentation/ring_ground.h) puts them on the road (0.77 of its points before, 1.0 since).
    {"VLP16", 16, 15.0, 2.0, 0.9, 0.03},
};

sim::Primitive box(const std::string& name, PointClass point_class, const Eigen::Vector3d& low,
                   const Eigen::Vector3d& high) {
  sim::Primitive primitive;
  primitive.name = name;
  primitive.point_class = point_class;
  primitive.center = (low + high) / 2;
  primitive.size = high - low;
  return primitive;
}

sim::Scene street() {
  sim::Scene scene;
  scene.name = "street";
  scene.primitives = {
      box("road", PointClass::kGround, {-60, -30, -0.2}, {60, 5, 0}),
      box("pavement", PointClass::kGround, {-60, 5, -0.2}, {60, 9, kKerb}),
      // A parked car: body (bonnet and boot 0.9 m up) and cabin (roof 1.45 m up).
      box("car", PointClass::kObstacle, {4, 2.6, 0.3}, {8.2, 4.4, 0.9}),
      box("car", PointClass::kObstacle, {5.2, 2.7, 0.9}, {7.4, 4.3, 1.45}),
      box("facade", PointClass::kWall, {-60, 9, 0}, {60, 9.3, 12}),
  };
  return scene;
}

struct SimulatedFrame {
  Scan scan;
  std::vector<int> primitive;  // per point, the primitive hit (-1: none)
  std::vector<int> laser;      // per point, its laser's place in the firing
};

// The order a frame keeps its returns in: ring after ring, as KITTI stores them, or firing after
// firing (one return of each laser per column of azimuth), as a driver sends them; a VLP-16 fires
// its lasers interleaved (-15, 1, -13, 3, ... 15 deg), an HDL-32E its lower and upper halves in
// turn (-30.67, -9.33, -29.33, -8, ... deg), the HDL-64E here from the top down.
enum class Order { kRingAfterRing, kFiringAfterFiring };

// The ring the k-th laser of a firing belongs to (ring 0 the top one).
int ringOfFiring(const Head& head, int k) {
  if (head.rings == 16) {
    const int elevation = k % 2 == 0 ? k - 15 : k;  // the VLP-16's interleaved firing
    return (15 - elevation) / 2;
  }
  if (head.rings == 32)  // even lasers up from the bottom ring, odd ones up from the 16th
    return k % 2 == 0 ? 31 - k / 2 : 15 - k / 2;
  return k;
}

// Sensor frame (x forward, z up) at the scene's (0, 0, kSensorHeight), with the frame's pose as a
// KITTI file gives it; no return where a beam meets nothing (the sky), as drivers drop them.
SimulatedFrame simulateFrame(const sim::Scene& scene, const Head& head,
                             Order order = Order::kRingAfterRing) {
  const sim::RayCaster caster(scene);
  const Eigen::Vector3d origin(0.0, 0.0, kSensorHeight);
  std::mt19937 random(64);
  std::normal_distribution<double> noise(0.0, kRangeNoise);
  SimulatedFrame frame;
  auto cast = [&](int ring, int a, int laser) {
    const double elevation = (head.top_elevation - ring * head.ring_step) * kDeg;
    const double azimuth = (a * 360.0 / kAzimuths - 180.0) * kDeg;
    const Eigen::Vector3d direction(std::cos(elevation) * std::cos(azimuth),
                                    std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
    const auto hit = caster.cast(origin, direction, kMaxRange);
    if (!hit) return;
    const Eigen::Vector3d p = direction * (hit->distance + noise(random));
    frame.scan.points.push_back({float(p.x()), float(p.y()), float(p.z())});
    frame.scan.status.push_back(PointStatus::kValid);
    frame.primitive.push_back(hit->primitive);
    frame.laser.push_back(laser);
  };
  if (order == Order::kRingAfterRing) {
    for (int ring = 0; ring < head.rings; ++ring) {
      ScanLine line;
      line.first = frame.scan.points.size();
      for (int a = 0; a < kAzimuths; ++a)
        cast(ring, a, ring);
      line.count = frame.scan.points.size() - line.first;
      frame.scan.lines.push_back(line);
    }
  } else {
    for (int a = 0; a < kAzimuths; ++a)
      for (int k = 0; k < head.rings; ++k)
        cast(ringOfFiring(head, k), a, k);
  }
  frame.scan.sensor_pose = SensorPose{};
  frame.scan.pose_source = PoseSource::kFile;
  return frame;
}

// Road, pavement and the car's upper part: points, and those classed ground.
struct StreetShares {
  std::size_t road = 0, road_ground = 0, pavement = 0, pavement_ground = 0, car_high = 0,
              car_high_ground = 0;
};

StreetShares countShares(const sim::Scene& scene, const Scan& scan,
                         const std::vector<int>& primitive_of,
                         const std::vector<PointClass>& point_classes) {
  StreetShares shares;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const std::string& name = scene.primitives[std::size_t(primitive_of[i])].name;
    const bool ground = point_classes[i] == PointClass::kGround;
    const double height = scan.points[i].z + kSensorHeight;
    if (name == "road") {
      ++shares.road;
      shares.road_ground += ground;
    } else if (name == "pavement") {
      ++shares.pavement;
      shares.pavement_ground += ground;
    } else if (name == "car" && height > 0.5) {
      ++shares.car_high;
      shares.car_high_ground += ground;
    }
  }
  std::cout << "[ figures  ] road " << shares.road_ground << " of " << shares.road
            << " ground, pavement " << shares.pavement_ground << " of " << shares.pavement
            << ", car above 0.5 m " << shares.car_high_ground << " of " << shares.car_high << "\n";
  return shares;
}

void expectStreetShares(const StreetShares& shares, const Head& head) {
  ASSERT_GT(shares.road, 0u);
  ASSERT_GT(shares.pavement, 0u);
  ASSERT_GT(shares.car_high, 0u);
  EXPECT_GE(double(shares.road_ground) / double(shares.road), head.road_share);
  EXPECT_GE(double(shares.pavement_ground) / double(shares.pavement), 0.8);
  EXPECT_EQ(shares.car_high_ground, 0u);
}

// The loader reorders the points into rings: each loaded point's primitive, found again by
// position.
std::vector<int> primitivesOfLoaded(const SimulatedFrame& frame, const Scan& scan) {
  auto byPosition = [](const Scan& s) {
    std::vector<std::size_t> index(s.size());
    for (std::size_t i = 0; i < index.size(); ++i)
      index[i] = i;
    std::sort(index.begin(), index.end(), [&](std::size_t a, std::size_t b) {
      const Point3f &p = s.points[a], &q = s.points[b];
      return std::tie(p.x, p.y, p.z) < std::tie(q.x, q.y, q.z);
    });
    return index;
  };
  const std::vector<std::size_t> order = byPosition(frame.scan), loaded = byPosition(scan);
  std::vector<int> primitive_of(scan.size());
  for (std::size_t k = 0; k < order.size() && k < loaded.size(); ++k)
    primitive_of[loaded[k]] = frame.primitive[order[k]];
  return primitive_of;
}

// The frame saved as an unorganised binary PCD of x, y, z (and, with kField, a `laser_id` per
// point: its laser's place in the firing, as VeloView exports it) and loaded again, level and
// upright as the ring-after-ring frame (a PCD's identity viewpoint says no pose).
enum class LaserId { kNone, kField };

Scan savedAndLoaded(const SimulatedFrame& frame, const std::filesystem::path& file,
                    LaserId laser_id) {
  {
    const bool with_id = laser_id == LaserId::kField;
    std::ofstream pcd(file);
    pcd << "VERSION 0.7\nFIELDS x y z" << (with_id ? " laser_id" : "") << "\nSIZE 4 4 4"
        << (with_id ? " 2" : "") << "\nTYPE F F F" << (with_id ? " U" : "") << "\nCOUNT 1 1 1"
        << (with_id ? " 1" : "") << "\nWIDTH " << frame.scan.size()
        << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << frame.scan.size() << "\nDATA binary\n";
    for (std::size_t i = 0; i < frame.scan.size(); ++i) {
      pcd.write(reinterpret_cast<const char*>(&frame.scan.points[i]), sizeof(Point3f));
      const auto laser = std::uint16_t(frame.laser[i]);
      if (with_id) pcd.write(reinterpret_cast<const char*>(&laser), sizeof(laser));
    }
  }
  Scan scan = loadScan(file);
  scan.sensor_pose = SensorPose{};
  scan.pose_source = PoseSource::kFile;
  return scan;
}

class MultiBeamStreet : public ::testing::TestWithParam<Head> {};

// Sparse rings too: each is a thin arc on a plane's support image, and only the cells between
// rings that face each other make the road an area (src/segmentation/ring_support.h). Without
// them the VLP-16's road had no supported area at all and the HDL-32E's was mostly obstacle.
TEST_P(MultiBeamStreet, RoadAndPavementAreGroundTheCarIsNot) {
  const sim::Scene scene = street();
  const SimulatedFrame frame = simulateFrame(scene, GetParam());
  const Scan& scan = frame.scan;
  ASSERT_EQ(describeSensor(scan).kind, SensorKind::kMultiBeam);

  const PipelineResult result = runPipeline(scan, SegmentationParams{});
  ASSERT_TRUE(result.trusted()) << result.analysis->reason;
  const Plane& reference =
      result.analysis->planes.planes[std::size_t(result.analysis->reference_ground)];
  EXPECT_NEAR(std::abs(reference.normal.z()), 1.0, 1e-3);
  EXPECT_NEAR(reference.offset, kSensorHeight, GetParam().height_tolerance);

  expectStreetShares(countShares(scene, scan, frame.primitive, result.point_classes), GetParam());
}

// The same street in firing order, saved without a ring field (an unorganised PCD of x, y, z, as a
// driver's points are often exported): the loader sees columns of a few returns each, zig-zagging
// in elevation for the VLP-16, and must give the frame its rings back, one line per ring.
TEST_P(MultiBeamStreet, AFrameInFiringOrderWithoutARingFieldGetsItsRingsBack) {
  const sim::Scene scene = street();
  const SimulatedFrame frame = simulateFrame(scene, GetParam(), Order::kFiringAfterFiring);
  test::TemporaryDirectory directory;
  const Scan scan = savedAndLoaded(frame, directory / "firing.pcd", LaserId::kNone);
  ASSERT_EQ(scan.size(), frame.scan.size());
  EXPECT_EQ(scan.lines.size(), std::size_t(GetParam().rings));
  ASSERT_EQ(describeSensor(scan).kind, SensorKind::kMultiBeam);

  const PipelineResult result = runPipeline(scan, SegmentationParams{});
  ASSERT_TRUE(result.trusted()) << result.analysis->reason;
  expectStreetShares(
      countShares(scene, scan, primitivesOfLoaded(frame, scan), result.point_classes), GetParam());
}

// The same rings, each with its returns in another order: starting where the frame was cut (a
// KITTI file's rings start ahead, a driver's behind the sensor), turning the other way, starting
// on either side of the back (+179.9 and -179.9 deg on neighbouring rings), and with returns a
// step or three out of azimuth order, as a frame corrected for the vehicle's motion holds them.
enum class RingStart {
  kBehind,
  kAhead,
  kClockwise,
  kEitherSideOfTheBack,
  kOutOfOrder,
  kTopRingFirst
};

Scan withRingsStarting(const Scan& frame, RingStart start) {
  Scan scan = frame;
  for (std::size_t l = 0; l < scan.lines.size(); ++l) {
    const ScanLine& ring = scan.lines[l];
    const auto first = scan.points.begin() + std::ptrdiff_t(ring.first);
    const auto end = first + std::ptrdiff_t(ring.count);
    switch (start) {
      case RingStart::kBehind:
        break;
      case RingStart::kAhead:
        std::rotate(first, first + std::ptrdiff_t(ring.count / 2), end);
        break;
      case RingStart::kClockwise:
        std::reverse(first, end);
        break;
      case RingStart::kEitherSideOfTheBack:
        if (l % 2 == 0) std::rotate(first, end - 1, end);
        break;
      case RingStart::kOutOfOrder:
        // Not at the same places on every ring: the walk would find the same order on both.
        for (std::size_t k = 40 + 13 * l % 97; k + 3 < ring.count; k += 97)
          std::swap(first[std::ptrdiff_t(k)], first[std::ptrdiff_t(k + 3)]);
        break;
      case RingStart::kTopRingFirst:
        break;
    }
  }
  if (start == RingStart::kTopRingFirst) return test::linesReversed(scan);
  return scan;
}

// The points' order within a ring says nothing about the street: the map must not change with it.
// KITTI's stored order (rings starting ahead, returns out of order by up to 0.7 deg) showed 18,128
// traversable cells on 000002.bin, against 80,094 with the same rings sorted by azimuth: the walk
// that pairs neighbouring rings stopped at the first return out of order and joined no ground
// beyond it.
// The rings' segments are compared with the next rings' in parts, one per thread and more; the
// parts are gathered in order, so the planes and the map do not depend on the number of threads.
TEST(MultiBeamStreetMap, IsTheSameForAnyNumberOfThreads) {
  const SimulatedFrame frame = simulateFrame(street(), kHeads[0]);
  const PipelineResult one = runPipeline(frame.scan, SegmentationParams{}, 1);
  ASSERT_TRUE(one.trusted()) << one.analysis->reason;
  for (const int threads : {2, 3}) {
    const PipelineResult result = runPipeline(frame.scan, SegmentationParams{}, threads);
    EXPECT_EQ(result.analysis->planes.planes.size(), one.analysis->planes.planes.size());
    EXPECT_TRUE(result.point_classes == one.point_classes) << threads << " threads";
    EXPECT_TRUE(result.map.labels == one.map.labels) << threads << " threads";
    EXPECT_TRUE(result.map.reach == one.map.reach) << threads << " threads";
  }
}

TEST(MultiBeamStreetMap, DoesNotDependOnWhereOrWhichWayItsRingsStart) {
  const Head& head = kHeads[0];
  const SimulatedFrame frame = simulateFrame(street(), head);
  const PipelineResult reference = runPipeline(frame.scan, SegmentationParams{});
  ASSERT_TRUE(reference.trusted()) << reference.analysis->reason;
  const auto traversable = std::count(reference.map.labels.begin(), reference.map.labels.end(),
                                      std::uint8_t(CellLabel::kTraversable));
  ASSERT_GT(traversable, 10000);
  for (const RingStart start :
       {RingStart::kAhead, RingStart::kClockwise, RingStart::kEitherSideOfTheBack,
        RingStart::kOutOfOrder, RingStart::kTopRingFirst}) {
    const PipelineResult result =
        runPipeline(withRingsStarting(frame.scan, start), SegmentationParams{});
    ASSERT_TRUE(result.trusted()) << result.analysis->reason;
    // The grids cover the ground seen, a few points more or less: cells are compared where they
    // lie, each reference cell with the one holding its centre (off the grid: unknown).
    const MapGrid& grid = reference.map.grid;
    std::size_t differing = 0;
    for (int row = 0; row < grid.height; ++row)
      for (int column = 0; column < grid.width; ++column) {
        const Eigen::Vector2d centre = grid.centre(column, row);
        const Eigen::Vector2i there = result.map.grid.cellOf(centre.x(), centre.y());
        const CellLabel label = result.map.grid.inside(there.x(), there.y())
                                    ? result.map.label(there.x(), there.y())
                                    : CellLabel::kUnknown;
        differing += label != reference.map.label(column, row);
      }
    std::cout << "[ figures  ] ring start " << int(start) << ": " << differing << " of "
              << reference.map.labels.size() << " cells differ (" << traversable
              << " traversable)\n";
    EXPECT_LE(double(differing), 0.02 * double(traversable)) << "ring start " << int(start);
  }
}

// The same street as VeloView exports it: firing after firing with a `laser_id` per point, the
// number of the laser in the firing (a VLP-16's laser 0 looks 15 deg down, laser 1 one degree up).
// Its lines must be its rings side by side in elevation, or the ground is triangulated between
// rings 16 deg apart: the map must be the ring-after-ring frame's.
TEST_P(MultiBeamStreet, ALaserIdFieldInFiringOrderGivesTheSameMap) {
  const sim::Scene scene = street();
  const SimulatedFrame frame = simulateFrame(scene, GetParam(), Order::kFiringAfterFiring);
  test::TemporaryDirectory directory;
  const Scan scan = savedAndLoaded(frame, directory / "laser_id.pcd", LaserId::kField);
  ASSERT_EQ(scan.lines.size(), std::size_t(GetParam().rings));
  // Lines side by side in elevation: up or down all the way (laser numbers that follow the
  // elevation are kept, top down here for the HDL-64E; interleaved ones are replaced).
  const SensorGeometry sensor = describeSensor(scan);
  ASSERT_EQ(sensor.kind, SensorKind::kMultiBeam);
  const std::vector<double>& elevation = sensor.line_angle;
  ASSERT_GE(elevation.size(), 2u);
  const double way = elevation.back() > elevation.front() ? 1.0 : -1.0;
  for (std::size_t l = 1; l < elevation.size(); ++l)
    EXPECT_GT(way * (elevation[l] - elevation[l - 1]), 0.0) << l;

  const PipelineResult result = runPipeline(scan, SegmentationParams{});
  const PipelineResult reference =
      runPipeline(simulateFrame(scene, GetParam()).scan, SegmentationParams{});
  ASSERT_TRUE(result.trusted()) << result.analysis->reason;
  ASSERT_TRUE(reference.trusted()) << reference.analysis->reason;
  // Planes are grown between neighbouring lines too: the road is ground as ring after ring (the
  // VLP-16's map is empty, its rings vouching for no ground beyond its lowest ring's 6.5 m).
  expectStreetShares(
      countShares(scene, scan, primitivesOfLoaded(frame, scan), result.point_classes), GetParam());
  // The ground the rings' triangles cover (the sparser heads show little green: their far rings
  // are too sparse to vouch for it), and what is green.
  auto groundCells = [](const PipelineResult& r) {
    const std::vector<std::int16_t>& plane = r.analysis->inputs.ground_plane;
    return double(std::count_if(plane.begin(), plane.end(), [](std::int16_t g) { return g >= 0; }));
  };
  auto traversable = [](const PipelineResult& r) {
    return double(std::count(r.map.labels.begin(), r.map.labels.end(),
                             std::uint8_t(CellLabel::kTraversable)));
  };
  std::cout << "[ figures  ] ground cells " << groundCells(result) << " against "
            << groundCells(reference) << " ring after ring, traversable " << traversable(result)
            << " against " << traversable(reference) << "\n";
  EXPECT_NEAR(groundCells(result), groundCells(reference), 0.02 * groundCells(reference));
  EXPECT_NEAR(traversable(result), traversable(reference), 0.03 * traversable(reference) + 20);
}

INSTANTIATE_TEST_SUITE_P(Heads, MultiBeamStreet, ::testing::ValuesIn(kHeads),
                         [](const ::testing::TestParamInfo<Head>& head) {
                           return std::string(head.param.name);
                         });

}  // namespace
}  // namespace clearway
