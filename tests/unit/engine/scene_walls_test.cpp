// Stage 6's wall boxes stand upright in the map frame: aligned with the wall, on the ground, below
// the ceiling (issue #13, defect 4: they were built on the support image's arbitrary in-plane axes
// and stood tilted through floor and ceiling).

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "engine_fixtures.h"

namespace clearway {
namespace {

// Tolerances: how far from vertical an axis may lean, how far the bottom may be off the ground.
constexpr double kUprightCos = 0.995;  // about 6 degrees
constexpr double kGroundTolerance = 0.05;
// The garage scene's ceiling (resources/scenes/garage.json) [m].
constexpr double kGarageCeiling = 2.6;

TEST(SceneWalls, GarageWallsAreUprightBoxesStandingOnTheGround) {
  const test::SimulatedRun run = test::simulateAndSegment("garage", 300);
  ASSERT_TRUE(run.result.trusted());
  const Eigen::Isometry3d& map_from_scanner = run.result.analysis->map_from_scanner;
  ASSERT_GE(run.result.scene.walls.size(), 3U);
  int standing = 0, hanging = 0;
  for (const SceneBox& box : run.result.scene.walls) {
    const Eigen::Matrix3d axes = map_from_scanner.linear() * box.axes.cast<double>();
    // The box's own z is the map's up; its x runs along the wall, horizontally.
    EXPECT_GT(axes.col(2).z(), kUprightCos);
    EXPECT_LT(std::abs(axes.col(0).z()), 1.0 - kUprightCos + 1e-9);
    const Eigen::Vector3d centre = map_from_scanner * box.center.cast<double>();
    const double bottom = centre.z() - box.half_size.z(), top = centre.z() + box.half_size.z();
    // Nothing reaches below the ground or through the garage's 2.6 m ceiling.
    EXPECT_GT(bottom, -kGroundTolerance);
    EXPECT_LT(top, kGarageCeiling + kGroundTolerance);
    standing += std::abs(bottom) < kGroundTolerance && top > 1.5;
    hanging += bottom > 1.5;
  }
  // The garage's walls stand on the ground: back, left, right, and the front wall on both sides
  // of the open door, over which its lintel hangs (a box spanning the whole plane closed the door).
  EXPECT_GE(standing, 5);
  EXPECT_GE(hanging, 1);
}

}  // namespace
}  // namespace clearway
