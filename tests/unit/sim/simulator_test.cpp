#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "clearway/sim/builtin_scenes.h"
#include "clearway/sim/ray_caster.h"
#include "clearway/sim/rosi_simulator.h"

namespace clearway::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

Scene floorOnly() {
  Scene scene;
  Primitive floor;
  floor.name = "floor";
  floor.point_class = PointClass::kGround;
  floor.center = {0, 0, -0.05};
  floor.size = {100, 100, 0.1};
  scene.primitives.push_back(floor);
  return scene;
}

SensorModel noiseless(int lines) {
  SensorModel sensor;
  sensor.lines = lines;
  sensor.range_noise_sigma = 0.0;
  sensor.max_range = 80.0;
  return sensor;
}

TEST(RosiSimulator, HasTheRosiStructure) {
  const Scene scene = *builtinScene("garage");
  SensorModel sensor;
  sensor.lines = 80;
  const SimulatedScan simulated = simulateRosi(scene, sensor, defaultPlacement(scene));
  const Scan& scan = simulated.scan;
  EXPECT_EQ(scan.size(), 80u * 180u);
  EXPECT_TRUE(scan.isOrganised());
  EXPECT_EQ(scan.pointsPerLine(), 180u);
  EXPECT_NEAR(scan.lines[20].beta, 2 * std::numbers::pi * 20 / 80, 1e-12);
  EXPECT_NEAR(scan.alpha[179], 89.5 * kDeg, 1e-6);
  EXPECT_EQ(simulated.truth.classes.size(), scan.size());
}

TEST(RosiSimulator, PointsFollowThePaperEquations) {
  // Axis straight down 2 m above a floor: every beam but alpha = 0 hits at d = 2 / sin(alpha).
  ScannerPlacement placement;
  placement.position = {0, 0, 2.0};
  placement.axis = {0, 0, -1};
  const SimulatedScan simulated = simulateRosi(floorOnly(), noiseless(16), placement);
  const Scan& scan = simulated.scan;
  for (std::size_t line = 0; line < 16; ++line) {
    const double beta = scan.lines[line].beta;
    for (int k = 10; k < 180; k += 13) {
      const std::size_t i = line * 180 + std::size_t(k);
      ASSERT_TRUE(scan.isValid(i));
      const double alpha = k * 0.5 * kDeg;
      const double d = 2.0 / std::sin(alpha);
      EXPECT_NEAR(scan.points[i].x, std::cos(beta) * std::cos(alpha) * d, 1e-4);
      EXPECT_NEAR(scan.points[i].y, std::sin(beta) * std::cos(alpha) * d, 1e-4);
      EXPECT_NEAR(scan.points[i].z, std::sin(alpha) * d, 1e-4);
      EXPECT_EQ(simulated.truth.classes[i], PointClass::kGround);
    }
    // alpha = 0 runs parallel to the floor: no return.
    EXPECT_FALSE(scan.isValid(line * 180));
  }
}

TEST(RosiSimulator, TruthSurfacesContainTheirPoints) {
  const Scene scene = *builtinScene("hallway");
  const SimulatedScan simulated = simulateRosi(scene, noiseless(120), defaultPlacement(scene));
  std::map<int, const SurfaceTruth*> by_id;
  for (const SurfaceTruth& s : simulated.truth.seen_surfaces)
    by_id[s.id] = &s;
  std::size_t checked = 0;
  for (std::size_t i = 0; i < simulated.scan.size(); ++i) {
    if (!simulated.scan.isValid(i)) continue;
    const SurfaceTruth& surface = *by_id.at(simulated.truth.surfaces[i]);
    ASSERT_TRUE(surface.planar);
    const Point3f& p = simulated.scan.points[i];
    EXPECT_NEAR(surface.normal.dot(Eigen::Vector3d(p.x, p.y, p.z)), surface.offset, 1e-3)
        << surface.primitive << " face " << surface.face;
    ++checked;
  }
  EXPECT_GT(checked, 10000u);
}

TEST(RosiSimulator, RayCasterFindsTheNearestFace) {
  const RayCaster caster(floorOnly());
  const auto hit = caster.cast({1, 2, 3}, {0, 0, -1}, 100);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->distance, 3.0, 1e-12);
  EXPECT_EQ(hit->face, 5);  // +z face of the slab
  EXPECT_NEAR(hit->normal.z(), 1.0, 1e-12);
  EXPECT_FALSE(caster.cast({1, 2, 3}, {0, 0, 1}, 100)) << "nothing above";
  EXPECT_FALSE(caster.cast({1, 2, 3}, {0, 0, -1}, 2.5)) << "beyond max range";
}

TEST(RosiSimulator, GlassAndRangeLimitGiveNoReturn) {
  const Scene scene = *builtinScene("glass");
  SensorModel sensor = noiseless(100);
  sensor.max_range = 30.0;
  const SimulatedScan simulated = simulateRosi(scene, sensor, defaultPlacement(scene));
  // Nothing from the glass wall itself ever appears in the truth.
  for (const SurfaceTruth& s : simulated.truth.seen_surfaces)
    EXPECT_NE(s.primitive, "glass_wall");
  EXPECT_GT(simulated.scan.size() - simulated.scan.validCount(), 2000u);

  SensorModel short_range = sensor;
  short_range.max_range = 2.0;
  const SimulatedScan near = simulateRosi(scene, short_range, defaultPlacement(scene));
  for (std::size_t i = 0; i < near.scan.size(); ++i) {
    if (!near.scan.isValid(i)) continue;
    const Point3f& p = near.scan.points[i];
    EXPECT_LE(std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z), 2.0 + 1e-4);
  }
}

TEST(RosiSimulator, NoiseIsSeededAndHasTheAskedSigma) {
  const Scene scene = floorOnly();
  ScannerPlacement placement;
  placement.position = {0, 0, 2.0};
  placement.axis = {0, 0, -1};
  SensorModel sensor = noiseless(40);
  sensor.range_noise_sigma = 0.01;
  const SimulatedScan a = simulateRosi(scene, sensor, placement);
  const SimulatedScan b = simulateRosi(scene, sensor, placement);
  sensor.seed = 2;
  const SimulatedScan c = simulateRosi(scene, sensor, placement);
  double sum_squared = 0.0;
  std::size_t n = 0;
  bool differs = false;
  for (std::size_t i = 0; i < a.scan.size(); ++i) {
    if (!a.scan.isValid(i)) continue;
    EXPECT_EQ(a.scan.points[i].z, b.scan.points[i].z);
    differs |= a.scan.points[i].z != c.scan.points[i].z;
    // Height error along the beam: (range error) * sin(alpha).
    const double range_error = (a.scan.points[i].z - 2.0) / std::sin(a.scan.alpha[i]);
    sum_squared += range_error * range_error;
    ++n;
  }
  EXPECT_TRUE(differs);
  EXPECT_NEAR(std::sqrt(sum_squared / double(n)), 0.01, 0.001);
}

TEST(RosiSimulator, MixedPixelsAppearOnlyAtDepthEdges) {
  const Scene scene = *builtinScene("garage");
  SensorModel sensor = noiseless(100);
  const SimulatedScan clean = simulateRosi(scene, sensor, defaultPlacement(scene));
  sensor.mixed_pixels = true;
  const SimulatedScan mixed = simulateRosi(scene, sensor, defaultPlacement(scene));
  std::size_t changed = 0;
  for (std::size_t i = 0; i < clean.scan.size(); ++i)
    if (clean.scan.isValid(i) && clean.scan.points[i].x != mixed.scan.points[i].x) ++changed;
  EXPECT_GT(changed, 10u);
  EXPECT_LT(changed, clean.scan.size() / 20);
}

TEST(RosiSimulator, LinesFollowTheTurntableSpeed) {
  EXPECT_EQ(SensorModel::linesForSpeed(45.0), 300);  // 37.5 lines/s * 8 s
  EXPECT_EQ(SensorModel::linesForSpeed(168.75), 80);
}

// A scanner inside a solid would see the solid's far faces from within: a scene that cannot be,
// whose truth the map would be judged against (a sweep placed the RoSi inside the stairwell's
// walls and counted up to 295 false cells).
TEST(RosiSimulator, AScannerInsideASolidIsRefusedWithItsName) {
  const sim::Scene scene = *sim::builtinScene("stairwell");
  sim::ScannerPlacement placement = sim::defaultPlacement(scene);
  sim::SensorModel sensor;
  sensor.lines = 4;
  placement.position = {1.0, 0.8, 1.0};  // the left wall spans y 0.7-0.9
  try {
    sim::simulateRosi(scene, sensor, placement);
    ADD_FAILURE() << "a scanner inside the wall was simulated";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("inside 'left_wall'"), std::string::npos)
        << error.what();
  }
  placement.position = {1.0, 0.95, 1.0};  // beside the wall, outside the stairwell: free space
  EXPECT_EQ(sim::simulateRosi(scene, sensor, placement).scan.lines.size(), 4U);
  // A cylinder holds its inside too.
  sim::Primitive pipe;
  pipe.shape = sim::Shape::kCylinder;
  pipe.center = {2.0, 0.0, 1.0};
  pipe.size = {0.4, 0.4, 3.0};
  pipe.roll_deg = 90.0;  // along y
  EXPECT_TRUE(pipe.holdsInside({2.1, 1.2, 1.1}));
  EXPECT_FALSE(pipe.holdsInside({2.1, 1.6, 1.1}));    // beyond its end
  EXPECT_FALSE(pipe.holdsInside({2.15, 0.0, 1.15}));  // in its box, outside its round
}

TEST(RosiSimulator, TiltedAxisStillSeesTheSameWorld) {
  const Scene scene = *builtinScene("garage");
  ScannerPlacement placement = defaultPlacement(scene);
  placement.axis = Eigen::AngleAxisd(30 * kDeg, Eigen::Vector3d::UnitX()) * placement.axis;
  placement.axis_roll_deg = 40;
  const SimulatedScan simulated = simulateRosi(scene, noiseless(100), placement);
  const Eigen::Isometry3d world_from_scanner = placement.worldFromScanner();
  for (std::size_t i = 0; i < simulated.scan.size(); i += 7) {
    if (!simulated.scan.isValid(i) || simulated.truth.classes[i] != PointClass::kGround) continue;
    const Point3f& p = simulated.scan.points[i];
    EXPECT_NEAR((world_from_scanner * Eigen::Vector3d(p.x, p.y, p.z)).z(), 0.0, 1e-3);
  }
}

}  // namespace
}  // namespace clearway::sim
