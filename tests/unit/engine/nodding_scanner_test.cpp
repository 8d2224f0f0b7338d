// A nodding scanner's file (3DTK's walkway, octomap's stairs): a 2D scanner tilted about a
// horizontal axis, its points in a level frame, no turntable angle per line. Its fans all point
// forward, so their directions about z do not order them; the axis their planes hold does
// (docs/ALGORITHM.md, section 0), and the density check measures its steps about that axis.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "clearway/eval/evaluation.h"
#include "clearway/pipeline.h"
#include "clearway/sim/builtin_scenes.h"
#include "engine_fixtures.h"

namespace clearway {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// The scene's own scanner position, the turntable axis sideways and tilted 17 deg down.
sim::ScannerPlacement noddingPlacement(const sim::Scene& scene) {
  sim::ScannerPlacement placement = sim::defaultPlacement(scene);
  placement.axis = Eigen::Vector3d(0.0, 1.0, -0.3).normalized();
  return placement;
}

TEST(NoddingScanner, ItsFansAreFoundToTurnAboutTheirAxis) {
  const sim::Scene scene = *sim::builtinScene("garage");
  sim::SensorModel sensor;
  sensor.lines = 200;
  const sim::ScannerPlacement placement = noddingPlacement(scene);
  const test::SimulatedRun run = test::simulateNodding(scene, sensor, placement);
  ASSERT_TRUE(run.result.trusted()) << run.result.reason;
  const SensorGeometry& geometry = run.result.analysis->sensor;
  ASSERT_TRUE(geometry.tilted_axis.has_value());
  EXPECT_GT(std::abs(geometry.tilted_axis->dot(placement.axis.normalized())), std::cos(1.0 * kDeg));
  EXPECT_NEAR(geometry.between_line_step, 360.0 / sensor.lines * kDeg, 0.05 * kDeg);
  EXPECT_TRUE(geometry.closed_turn);
}

// The scenes the sparse table runs, seen by a nodding scanner at 100 and 200 lines (3.6 and
// 1.8 deg between fans, the fans' returns 0.5 deg apart): from fan to fan the beam moves its
// sample outwards on the ground, within a fan sideways, the other way round from a RoSi's.
class NoddingScenes : public ::testing::TestWithParam<std::tuple<const char*, int>> {};

TEST_P(NoddingScenes, ShowOpenGroundAndNoFalseCells) {
  const auto [name, lines] = GetParam();
  const sim::Scene scene = *sim::builtinScene(name);
  sim::SensorModel sensor;
  sensor.lines = lines;
  const test::SimulatedRun run = test::simulateNodding(scene, sensor, noddingPlacement(scene));
  ASSERT_TRUE(run.result.trusted()) << run.result.reason;
  const eval::Evaluation e = test::evaluateRun(run);
  std::cout << "[ figures  ] " << name << " at " << lines << " lines: " << e.map.traversable_cells
            << " traversable cells, " << e.map.false_traversable_cells << " false\n";
  EXPECT_GT(e.map.traversable_cells, 300U);
  EXPECT_EQ(e.map.false_traversable_cells, 0U);
}

INSTANTIATE_TEST_SUITE_P(Scenes, NoddingScenes,
                         ::testing::Combine(::testing::Values("garage", "hallway", "doorways",
                                                              "outdoor"),
                                            ::testing::Values(100, 200)));

}  // namespace
}  // namespace clearway
