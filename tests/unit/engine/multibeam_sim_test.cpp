// A multi-beam frame of a simulated street with known geometry (docs/ALGORITHM.md, "Multi-beam
// frames"): the rings of a head 1.73 m above a road (an HDL-64E's 64 rings 0.42 deg apart, an
// HDL-32E's 32 rings 1.33 deg apart, a VLP-16's 16 rings 2 deg apart), a pavement behind a kerb
// lower than the robot's step, a parked car and a facade, ray-cast by our own simulator. The road
// and the pavement are ground; the car's roof and bonnet, flat and below the sensor, are not.

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>
#include <random>
#include <string>

#include "clearway/pipeline.h"
#include "clearway/sensor_geometry.h"
#include "clearway/sim/ray_caster.h"
#include "clearway/sim/scene.h"

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
    // the 2 m a plane's area spans between rings), each on its own: a quarter of the road's
    // points are not ground, and the plane rests on fewer rings.
    {"VLP16", 16, 15.0, 2.0, 0.75, 0.03},
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
};

// Ring after ring, as KITTI stores them; sensor frame (x forward, z up) at the scene's
// (0, 0, kSensorHeight), with the frame's pose as a KITTI file gives it.
SimulatedFrame simulateFrame(const sim::Scene& scene, const Head& head) {
  const sim::RayCaster caster(scene);
  const Eigen::Vector3d origin(0.0, 0.0, kSensorHeight);
  std::mt19937 random(64);
  std::normal_distribution<double> noise(0.0, kRangeNoise);
  SimulatedFrame frame;
  for (int ring = 0; ring < head.rings; ++ring) {
    const double elevation = (head.top_elevation - ring * head.ring_step) * kDeg;
    ScanLine line;
    line.first = frame.scan.points.size();
    for (int a = 0; a < kAzimuths; ++a) {
      const double azimuth = (a * 360.0 / kAzimuths - 180.0) * kDeg;
      const Eigen::Vector3d direction(std::cos(elevation) * std::cos(azimuth),
                                      std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
      const auto hit = caster.cast(origin, direction, kMaxRange);
      if (!hit) continue;  // sky: a KITTI frame keeps no return
      const Eigen::Vector3d p = direction * (hit->distance + noise(random));
      frame.scan.points.push_back({float(p.x()), float(p.y()), float(p.z())});
      frame.scan.status.push_back(PointStatus::kValid);
      frame.primitive.push_back(hit->primitive);
    }
    line.count = frame.scan.points.size() - line.first;
    frame.scan.lines.push_back(line);
  }
  frame.scan.sensor_pose = SensorPose{};
  frame.scan.pose_source = PoseSource::kFile;
  return frame;
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

  // Per primitive: points, and those classed ground; the car's split at 0.5 m above the road.
  std::size_t road = 0, road_ground = 0, pavement = 0, pavement_ground = 0, car_high = 0,
              car_high_ground = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const std::string& name = scene.primitives[std::size_t(frame.primitive[i])].name;
    const bool ground = result.point_classes[i] == PointClass::kGround;
    const double height = scan.points[i].z + kSensorHeight;
    if (name == "road") {
      ++road;
      road_ground += ground;
    } else if (name == "pavement") {
      ++pavement;
      pavement_ground += ground;
    } else if (name == "car" && height > 0.5) {
      ++car_high;
      car_high_ground += ground;
    }
  }
  std::cout << "[ figures  ] road " << road_ground << " of " << road << " ground, pavement "
            << pavement_ground << " of " << pavement << ", car above 0.5 m " << car_high_ground
            << " of " << car_high << "\n";
  ASSERT_GT(road, 0u);
  ASSERT_GT(pavement, 0u);
  ASSERT_GT(car_high, 0u);
  EXPECT_GE(double(road_ground) / double(road), GetParam().road_share);
  EXPECT_GE(double(pavement_ground) / double(pavement), 0.8);
  EXPECT_EQ(car_high_ground, 0u);
}

INSTANTIATE_TEST_SUITE_P(Heads, MultiBeamStreet, ::testing::ValuesIn(kHeads),
                         [](const ::testing::TestParamInfo<Head>& head) {
                           return std::string(head.param.name);
                         });

}  // namespace
}  // namespace clearway
