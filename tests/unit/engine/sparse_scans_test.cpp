// Sparse scans never lie: at any line count, straight or tilted, no cell is shown traversable
// (green or careful) where the simulator's truth says the robot cannot stand. A subset of the
// table in docs/ALGORITHM.md; scripts/sparse-table produces the whole table with clearway-cli.

#include <gtest/gtest.h>

#include <string>
#include <tuple>

#include "clearway/eval/evaluation.h"
#include "engine_fixtures.h"

namespace clearway {
namespace {

using SparseCase = std::tuple<const char*, int, double>;  // scene, lines, tilt [deg]

class SparseScans : public ::testing::TestWithParam<SparseCase> {};

TEST_P(SparseScans, NoFalseTraversableCell) {
  const auto [scene, lines, tilt] = GetParam();
  const auto run = test::simulateAndSegment(scene, lines, SegmentationParams{}, tilt);
  eval::SegmentationResult result;
  const RobotParams robot;
  result.robot = {robot.width, robot.length, robot.height, robot.max_step};
  result.map = eval::resultMapOf(run.result.map.grid, run.result.map.labels,
                                 run.result.analysis.map_from_scanner);
  result.has_map = true;
  const eval::Evaluation e = eval::evaluate(run.simulated.truth, result);
  EXPECT_EQ(e.map.false_traversable_cells, 0u)
      << scene << " at " << lines << " lines, tilt " << tilt << ": " << e.map.traversable_cells
      << " traversable cells";
}

INSTANTIATE_TEST_SUITE_P(
    ScenesLinesTilts, SparseScans,
    ::testing::Combine(::testing::Values("garage", "hallway", "doorways", "outdoor", "stairwell"),
                       ::testing::Values(20, 40, 80), ::testing::Values(0.0, 25.0)),
    [](const ::testing::TestParamInfo<SparseCase>& test) {
      return std::string(std::get<0>(test.param)) + "_" + std::to_string(std::get<1>(test.param)) +
             "_lines_tilt_" + std::to_string(int(std::get<2>(test.param)));
    });

}  // namespace
}  // namespace clearway
