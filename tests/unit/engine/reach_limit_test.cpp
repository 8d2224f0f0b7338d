// Why the robot's reach stops short (TraversabilityMap::reach_limit), on hand-built map inputs:
// an island of seen ground around the robot (a car-mounted sensor's blind zone), a room whose
// walls shut it in, and an open floor where nothing needs saying.

#include <gtest/gtest.h>

#include <string>

#include "clearway/traversability/reachability.h"
#include "clearway/traversability/traversability_map.h"
#include "hand_built_map.h"

namespace clearway {
namespace {

using test::HandBuiltMap;

TraversabilityMap mapOf(const HandBuiltMap& built) {
  return computeTraversability(built.analysis(), RobotParams{}, MapParams{}, 2);
}

bool mentions(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Seen ground over [-kFar, kFar]^2 but for a ring of unseen ground from kIsland to kBlind around
// the robot at the origin: the rings of a multi-beam sensor never see the ground around the car.
constexpr double kFar = 5.0, kIsland = 0.9, kBlind = 2.0;

HandBuiltMap islandInUnseenRing() {
  HandBuiltMap built(-kFar - 0.5, -kFar - 0.5, kFar + 0.5, kFar + 0.5);
  built.floor(-kIsland, -kIsland, kIsland, kIsland)
      .floor(-kFar, -kFar, kFar, -kBlind)
      .floor(-kFar, kBlind, kFar, kFar)
      .floor(-kFar, -kBlind, -kBlind, kBlind)
      .floor(kBlind, -kBlind, kFar, kBlind)
      .robotAt(0.0, 0.0, 0.0);
  return built;
}

TEST(ReachLimit, AnIslandInUnseenGroundSaysTheGroundAroundWasNotSeen) {
  const TraversabilityMap map = mapOf(islandInUnseenRing());
  ASSERT_GT(map.reachable_cells, 0U);
  ASSERT_GT(map.fits_not_reachable_cells, map.reachable_cells);
  EXPECT_TRUE(mentions(map.reach_limit, "not seen")) << map.reach_limit;
  EXPECT_FALSE(mentions(map.reach_limit, "shut in")) << map.reach_limit;
  // The nearest cell it fits in lies beyond the unseen ring, with room for the box's half width.
  EXPECT_TRUE(mentions(map.reach_limit, "nearest such cell is 2.")) << map.reach_limit;
  // A goal beyond the ring is refused with the same words.
  const GoalResult goal = planPath(map, 3.5, 3.5);
  EXPECT_FALSE(goal.reachable);
  EXPECT_TRUE(mentions(goal.reason, "not seen")) << goal.reason;
}

TEST(ReachLimit, ARoomWhoseWallsShutTheRobotInSaysSo) {
  HandBuiltMap built(-kFar - 0.5, -kFar - 0.5, kFar + 0.5, kFar + 0.5);
  built.floor(-kFar, -kFar, kFar, kFar).robotAt(0.0, 0.0, 0.0);
  // A closed room of 1.8 x 1.4 m around the robot (1.2 x 0.85 m): the box fits and turns a little.
  const Eigen::Vector2d corners[] = {{-0.9, -0.7}, {0.9, -0.7}, {0.9, 0.7}, {-0.9, 0.7}};
  for (int side = 0; side < 4; ++side)
    built.face(corners[side], corners[(side + 1) % 4], 0.2, 1.2);
  const TraversabilityMap map = mapOf(built);
  ASSERT_GT(map.reachable_cells, 0U);
  ASSERT_GT(map.fits_not_reachable_cells, map.reachable_cells);
  EXPECT_TRUE(mentions(map.reach_limit, "shut in")) << map.reach_limit;
  EXPECT_TRUE(mentions(map.reach_limit, "wall")) << map.reach_limit;
  EXPECT_FALSE(mentions(map.reach_limit, "not seen")) << map.reach_limit;
}

TEST(ReachLimit, AnOpenFloorNeedsNoWords) {
  HandBuiltMap built(-kFar - 0.5, -kFar - 0.5, kFar + 0.5, kFar + 0.5);
  built.floor(-kFar, -kFar, kFar, kFar).robotAt(0.0, 0.0, 0.0);
  const TraversabilityMap map = mapOf(built);
  EXPECT_GT(map.reachable_cells, 1000U);
  EXPECT_TRUE(map.reach_limit.empty()) << map.reach_limit;
}

}  // namespace
}  // namespace clearway
