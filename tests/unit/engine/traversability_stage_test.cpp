// The traversability stage alone (computeTraversability on hand-built map inputs): corridors 2 cm
// wider and narrower than the robot, lintels above and below its height, steps above and below
// its step, an open floor. A failure here is the stage's, not the segmentation's.

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <numbers>
#include <string>
#include <vector>

#include "clearway/traversability/reachability.h"
#include "clearway/traversability/traversability_map.h"
#include "hand_built_map.h"

namespace clearway {
namespace {

using test::HandBuiltMap;

// The default robot, spelled out: the cases below are sized against it.
RobotParams testRobot() {
  RobotParams robot;
  robot.width = 0.85;
  robot.length = 1.2;
  robot.height = 1.5;
  robot.max_step = 0.1;
  return robot;
}

// The margin the issue names: a passage this much wider or narrower than the robot [m].
constexpr double kTwoCentimetres = 0.02;
// Heights of a wall's measured points above the floor [m]: from above the step to below the
// robot's top, so each blocks.
constexpr double kWallLow = 0.2, kWallHigh = 1.2;

TraversabilityMap mapOf(const HandBuiltMap& built, const RobotParams& robot = testRobot()) {
  return computeTraversability(built.analysis(), robot, MapParams{}, 2);
}

struct Cell {
  CellLabel label;
  CellReason reason;
  bool reachable;
};

Cell cellAt(const TraversabilityMap& map, double x, double y) {
  const Eigen::Vector2i c = map.grid.cellOf(x, y);
  EXPECT_TRUE(map.grid.inside(c.x(), c.y())) << "(" << x << ", " << y << ") is off the map";
  if (!map.grid.inside(c.x(), c.y())) return {CellLabel::kUnknown, CellReason::kNone, false};
  const std::size_t i = map.grid.index(c.x(), c.y());
  return {CellLabel(map.labels[i]), CellReason(map.reasons[i]), map.reach[i] != 0};
}

std::string describe(const Cell& cell) {
  return std::string(labelName(cell.label)) + " (" + std::string(reasonName(cell.reason)) + ")";
}

// Whether the cells on the row y = 0.025 at each of `xs` are (or are not) too steep.
void expectTooSteep(const TraversabilityMap& map, std::initializer_list<double> xs,
                    bool too_steep = true) {
  for (double x : xs) {
    const Cell cell = cellAt(map, x, 0.025);
    EXPECT_EQ(reasonName(cell.reason) == "too steep", too_steep)
        << "at x = " << x << ": " << describe(cell);
  }
}

// A corridor along x, from x = 1 to 5, between walls `width` apart centred on y = 0, in an open
// room; the robot stands in the room at (-1.5, 0) facing +x.
HandBuiltMap corridor(double width) {
  HandBuiltMap built(-3.0, -1.5, 6.0, 1.5);
  built.floor(-2.75, -1.25, 5.75, 1.25).robotAt(-1.5, 0.0, 0.0);
  for (double side : {-1.0, 1.0})
    built.face({1.0, side * width / 2}, {5.0, side * width / 2}, kWallLow, kWallHigh);
  return built;
}

// Cells on the corridor's centre line, where the robot's whole box is inside the corridor.
constexpr double kInsideFrom = 2.2, kInsideTo = 3.8;
// The two cell rows either side of the centre line (cell centres at -2.5 and +2.5 cm).
constexpr double kCentreRows[] = {-0.025, 0.025};

TEST(TraversabilityStage, ACorridorTwoCentimetresWiderThanTheRobotIsCarefulAlongIt) {
  const TraversabilityMap map = mapOf(corridor(testRobot().width + kTwoCentimetres));
  for (double x = kInsideFrom; x <= kInsideTo; x += 0.1)
    for (double y : kCentreRows) {
      const Cell cell = cellAt(map, x, y);
      EXPECT_EQ(cell.label, CellLabel::kCareful)
          << "at (" << x << ", " << y << "): " << describe(cell);
      EXPECT_TRUE(cell.reachable) << "at (" << x << ", " << y << ")";
    }
  // One cell off the centre line the robot no longer fits (1 cm of play on each side).
  EXPECT_EQ(cellAt(map, 3.0, 0.075).reason, CellReason::kTooNarrow);
}

TEST(TraversabilityStage, ACorridorTwoCentimetresNarrowerThanTheRobotIsTooNarrow) {
  const TraversabilityMap map = mapOf(corridor(testRobot().width - kTwoCentimetres));
  for (double x = kInsideFrom; x <= kInsideTo; x += 0.1)
    for (double y : kCentreRows) {
      const Cell cell = cellAt(map, x, y);
      EXPECT_EQ(cell.label, CellLabel::kImpassable) << "at (" << x << ", " << y << ")";
      EXPECT_EQ(reasonName(cell.reason), "too narrow") << "at (" << x << ", " << y << ")";
      EXPECT_FALSE(cell.reachable);
    }
}

// A floor ending at x = 4 m at a raised slab whose first blocking returns lie a cell in (x
// = 4.075): the cell column between was not observed, and the slab's edge may lie anywhere in it.
// The box may not reach over it, though a gap between scan lines in the open is tolerated.
TEST(TraversabilityStage, AnUnobservedGapBesideAnObstacleIsNotReachedOver) {
  HandBuiltMap built(-3.0, -1.5, 6.0, 1.5);
  built.floor(-2.75, -1.25, 4.0, 1.25).robotAt(-1.5, 0.0, 0.0);
  for (double x = 4.075; x < 5.0; x += 0.05)
    for (double y = -1.225; y < 1.25; y += 0.05)
      built.point(x, y, 0.12);
  const TraversabilityMap map = mapOf(built);
  // From this cell the box's edge would lie 3-7 cm past x = 4 m, in the gap.
  const Cell reaching = cellAt(map, 3.625, 0.025);
  EXPECT_EQ(reaching.label, CellLabel::kImpassable) << describe(reaching);
  EXPECT_EQ(reasonName(reaching.reason), "too narrow");
  // Two cells back it stays short of the gap and fits.
  const Cell short_of = cellAt(map, 3.525, 0.025);
  EXPECT_TRUE(short_of.label == CellLabel::kCareful || short_of.label == CellLabel::kTraversable)
      << describe(short_of);
}

// Where the box fits nowhere only because the cells around were not seen (the floor's edge, with
// nothing standing there), nothing seen stops the robot: the cell is unknown, not red "too
// narrow". Beside a wall it stays too narrow: what was seen may be what keeps the box out.
TEST(TraversabilityStage, AFloorsUnseenEdgeIsUnknownNotTooNarrow) {
  HandBuiltMap built(-3.0, -1.5, 6.0, 1.5);
  built.floor(-2.75, -1.25, 5.75, 1.25).robotAt(-1.5, 0.0, 0.0);
  built.face({1.0, 1.0}, {5.0, 1.0}, kWallLow, kWallHigh);
  const TraversabilityMap map = mapOf(built);
  const Cell at_the_edge = cellAt(map, 0.0, -1.2);
  EXPECT_EQ(at_the_edge.label, CellLabel::kUnknown) << describe(at_the_edge);
  EXPECT_EQ(at_the_edge.reason, CellReason::kUnseenAround) << describe(at_the_edge);
  EXPECT_EQ(reasonName(at_the_edge.reason), "too little seen around it");
  const Cell by_the_wall = cellAt(map, 3.0, 0.9);
  EXPECT_EQ(by_the_wall.label, CellLabel::kImpassable) << describe(by_the_wall);
  EXPECT_EQ(by_the_wall.reason, CellReason::kTooNarrow) << describe(by_the_wall);
  // Open floor between them, unchanged.
  EXPECT_EQ(cellAt(map, 0.0, 0.0).label, CellLabel::kTraversable);
}

TEST(TraversabilityStage, AWideCorridorIsGreen) {
  const TraversabilityMap map = mapOf(corridor(testRobot().width + 0.3));
  for (double x = kInsideFrom; x <= kInsideTo; x += 0.1)
    EXPECT_EQ(cellAt(map, x, 0.025).label, CellLabel::kTraversable) << "at x = " << x;
}

// The wide corridor's +y wall holds a post at x = 3 seen by one scan line. The next line's beam,
// at the post's range, was 0.3 m into the corridor (wider than twice the step, the widest the
// density check lets an obstacle hide in) or 0.18 m, and went on; or it ended there, on the floor
// (the post's shadow may hide the rest of it); or it hit the wall too. The post may reach into the
// unseen wedge between (docs/ALGORITHM.md, "Where an obstacle ends between two lines"), over the
// robot's box on the centre line, unless the wall goes on or the beam saw a narrow wedge's end.
constexpr double kPostX = 3.0;
enum class NextLine { kNone, kPassedFar, kPassedNear, kEndedOnTheFloor, kHitTheWall };
HandBuiltMap corridorWithPost(NextLine next_line) {
  const double wall_y = (testRobot().width + 0.3) / 2;
  HandBuiltMap built = corridor(testRobot().width + 0.3);
  built.point(kPostX + 0.3, wall_y, 0.5);
  const std::size_t on_the_wall = built.points() - 1;
  built.point(kPostX, wall_y, 0.5);
  if (next_line == NextLine::kPassedFar)
    built.sweptPast(kPostX, wall_y - 0.3, 0.5, 2.0);
  else if (next_line == NextLine::kPassedNear)
    built.sweptPast(kPostX, wall_y - 0.18, 0.5, 2.0);
  else if (next_line == NextLine::kEndedOnTheFloor)
    built.sweptPast(kPostX, wall_y - 0.18, 0.5, 0.0);
  else if (next_line == NextLine::kHitTheWall)
    built.sweptOnto(on_the_wall);
  return built;
}

TEST(TraversabilityStage, AnObstacleMayReachIntoTheWedgeToTheNextLinesBeam) {
  // The centre line beside the post: green when nothing says the post reaches out, when the next
  // line hit the wall (the wall goes on), or when its beam went on past a narrow wedge; only
  // probably passable, too sparse, when the wedge is wide or the beam ended in it. Still
  // reachable: only the wedge is unseen.
  for (const NextLine seen : {NextLine::kNone, NextLine::kHitTheWall, NextLine::kPassedNear}) {
    const Cell cell = cellAt(mapOf(corridorWithPost(seen)), kPostX, 0.025);
    EXPECT_EQ(cell.label, CellLabel::kTraversable) << int(seen) << ": " << describe(cell);
  }
  for (const NextLine unseen : {NextLine::kPassedFar, NextLine::kEndedOnTheFloor}) {
    const TraversabilityMap map = mapOf(corridorWithPost(unseen));
    const Cell beside = cellAt(map, kPostX, 0.025);
    EXPECT_EQ(beside.label, CellLabel::kObstacle) << int(unseen) << ": " << describe(beside);
    EXPECT_EQ(beside.reason, CellReason::kSparse) << int(unseen) << ": " << describe(beside);
    EXPECT_TRUE(beside.reachable) << int(unseen);
    // Past the wedge the corridor is green again.
    const Cell beyond = cellAt(map, kPostX + 1.0, 0.025);
    EXPECT_EQ(beyond.label, CellLabel::kTraversable) << int(unseen) << ": " << describe(beyond);
  }
}

// A low return in the wide corridor's middle, 6 cm up (the robot drives over it), seen by one line
// only. The next line's beam, at its range, passed 4 cm beside it and went on: level with it, the
// obstacle cannot have risen between the two lines unseen: a low obstacle to drive over; 15 cm
// higher (a turntable whose axis points forward lays its lines one above the other beside it), the
// obstacle may rise between them past the step, and the cells it stands in are not vouched for.
// A 0.13 m box seen only along its low side face, its top between such lines, was driven over (a
// helper's clutter scene, 100 lines tilted 15 deg).
TEST(TraversabilityStage, ALowObstacleMayRiseBetweenLinesOneAboveTheOther) {
  for (const double next_line_height : {0.06, 0.21}) {
    HandBuiltMap built = corridor(testRobot().width + 0.3);
    built.point(kPostX, 0.025, 0.06).sweptPast(kPostX, 0.065, next_line_height, 2.0);
    const TraversabilityMap map = mapOf(built);
    // Orange either way (the paper's "probably passable obstacle"); only the second says why.
    const Cell over = cellAt(map, kPostX, 0.025);
    EXPECT_EQ(over.label, CellLabel::kObstacle) << describe(over);
    EXPECT_EQ(over.reason,
              next_line_height < testRobot().max_step ? CellReason::kNone : CellReason::kSparse)
        << next_line_height << ": " << describe(over);
    EXPECT_TRUE(over.reachable);
  }
}

TEST(TraversabilityStage, AnObstacleSeenByTwoLinesIsNotVouchedForBetweenThem) {
  // A pipe 1.3 m above an open floor, lower than the robot, running along y at x = 3. Two scan
  // lines hit it 1.4 m apart (a sparse scan at 7 m: 12 deg between lines), at the same range;
  // between them nothing was seen at its height. The box under the pipe, between the two returns,
  // would fit: the pipe most likely runs on from one to the other.
  HandBuiltMap built(-3.0, -2.5, 6.0, 2.5);
  built.floor(-2.75, -2.25, 5.75, 2.25).robotAt(-1.5, 0.0, 0.0);
  built.point(3.0, -0.7, 1.3);
  const std::size_t first_return = built.points() - 1;
  built.point(3.0, 0.7, 1.3).sweptOnto(first_return);
  const TraversabilityMap map = mapOf(built);
  const Cell under = cellAt(map, 3.0, 0.025);
  EXPECT_EQ(under.label, CellLabel::kObstacle) << describe(under);
  EXPECT_EQ(under.reason, CellReason::kSparse) << describe(under);
  // Clear of the pipe the floor is green.
  const Cell clear = cellAt(map, 1.5, 0.025);
  EXPECT_EQ(clear.label, CellLabel::kTraversable) << describe(clear);
}

// A robot wider than long (1.0 x 0.7 m) before a 0.2 m thick wall at x = 1.9-2.1 with a door
// `door` wide centred on y = 0; it stands at (-1.5, 0) facing the wall.
RobotParams wideRobot() {
  RobotParams robot = testRobot();
  robot.width = 1.0;
  robot.length = 0.7;
  return robot;
}
HandBuiltMap wallWithDoor(double door) {
  HandBuiltMap built(-3.0, -2.5, 7.0, 2.5);
  built.floor(-2.75, -2.25, 6.75, 2.25).robotAt(-1.5, 0.0, 0.0).wallPlane(std::numbers::pi / 2);
  for (double side : {-1.0, 1.0}) {
    for (double x : {1.9, 2.1})
      built.face({x, side * door / 2}, {x, side * 2.25}, kWallLow, kWallHigh);
    built.face({1.9, side * door / 2}, {2.1, side * door / 2}, kWallLow, kWallHigh);  // the jamb
  }
  return built;
}

TEST(TraversabilityStage, ADoorNarrowerThanAWideRobotIsTooNarrowWhereItFitsOnlyTurnedAcross) {
  // Turned across the 0.94 m door (its 0.7 m length across the opening, its 1.0 m width
  // straddling the wall) the box fits in the doorway, but the robot drives along its length and
  // there has 0.24 m to move: the doorway is no passage. The room beyond is open floor the robot
  // cannot get to.
  const TraversabilityMap narrow = mapOf(wallWithDoor(0.94), wideRobot());
  for (double y : kCentreRows) {
    const Cell doorway = cellAt(narrow, 2.0, y);
    EXPECT_EQ(doorway.label, CellLabel::kImpassable) << describe(doorway);
    EXPECT_EQ(doorway.reason, CellReason::kTooNarrow) << describe(doorway);
    EXPECT_FALSE(doorway.reachable);
  }
  const Cell room = cellAt(narrow, 4.5, 0.025);
  EXPECT_EQ(room.label, CellLabel::kTraversable) << describe(room);
  EXPECT_FALSE(room.reachable);
  // A door 6 cm wider than the robot is a passage, driven through square to the wall.
  const TraversabilityMap wide = mapOf(wallWithDoor(1.06), wideRobot());
  for (double y : kCentreRows) {
    const Cell doorway = cellAt(wide, 2.0, y);
    EXPECT_TRUE(robotFits(doorway.label)) << describe(doorway);
    EXPECT_TRUE(doorway.reachable);
  }
  EXPECT_TRUE(cellAt(wide, 4.5, 0.025).reachable);
}

// A corridor 2 cm wider than the robot running at 37 deg, between none of the uniform orientations
// (every 15 deg): the robot fits only along it, which the stage tries when a wall says so.
constexpr double kSlantDeg = 37.0;
HandBuiltMap slantedCorridor(bool with_wall_plane) {
  const double yaw = kSlantDeg * std::numbers::pi / 180.0;
  const Eigen::Vector2d along(std::cos(yaw), std::sin(yaw)), across(-along.y(), along.x());
  const double half_width = (testRobot().width + kTwoCentimetres) / 2;
  HandBuiltMap built(-3.0, -3.0, 6.0, 6.0);
  // The robot faces +x: its own heading, always tried, is not the corridor's.
  built.floor(-2.75, -2.75, 5.75, 5.75).robotAt(-1.5, -1.5, 0.0);
  for (double side : {-1.0, 1.0})
    built.face(1.0 * along + side * half_width * across, 5.0 * along + side * half_width * across,
               kWallLow, kWallHigh);
  if (with_wall_plane) built.wallPlane(yaw);
  return built;
}

// Labels of the cells whose centres lie within 2 cm of the slanted corridor's centre line, where
// the robot's whole box is inside it.
std::vector<CellLabel> slantedCentreLine(const TraversabilityMap& map) {
  const double yaw = kSlantDeg * std::numbers::pi / 180.0;
  const Eigen::Vector2d along(std::cos(yaw), std::sin(yaw)), across(-along.y(), along.x());
  std::vector<CellLabel> labels;
  for (int row = 0; row < map.grid.height; ++row)
    for (int column = 0; column < map.grid.width; ++column) {
      const Eigen::Vector2d centre = map.grid.centre(column, row);
      const double u = centre.dot(along), v = centre.dot(across);
      if (u >= kInsideFrom && u <= kInsideTo && std::abs(v) <= 0.02)
        labels.push_back(map.label(column, row));
    }
  return labels;
}

TEST(TraversabilityStage, ASlantedCorridorFitsOnlyAlongItsWall) {
  const auto along_wall = slantedCentreLine(mapOf(slantedCorridor(true)));
  const auto uniform_only = slantedCentreLine(mapOf(slantedCorridor(false)));
  ASSERT_FALSE(along_wall.empty());
  ASSERT_EQ(along_wall.size(), uniform_only.size());
  // With the wall's direction tried, the centre line is careful (1 cm of play on each side) ...
  EXPECT_EQ(std::count(along_wall.begin(), along_wall.end(), CellLabel::kCareful),
            std::ptrdiff_t(along_wall.size()));
  // ... with only the uniform orientations, 7 deg off at best, the box fits nowhere along it.
  EXPECT_EQ(std::count(uniform_only.begin(), uniform_only.end(), CellLabel::kImpassable),
            std::ptrdiff_t(uniform_only.size()));
}

// A closed corridor 1.1 m wide along x from -2 to 4.5 (the only floor on the map), the robot in
// it at (-0.5, 0) facing +x, and a lintel across it over x = 1.5 .. 1.7 at `lintel_height`. The
// robot fits along it with 12 cm to spare on each side, never across it (it is 1.2 m long).
HandBuiltMap corridorWithLintel(double lintel_height) {
  constexpr double kHalfWidth = 0.55;
  HandBuiltMap built(-2.5, -1.0, 5.0, 1.0);
  built.floor(-2.0, -kHalfWidth, 4.5, kHalfWidth).robotAt(-0.5, 0.0, 0.0);
  for (double side : {-1.0, 1.0})
    built.face({-2.0, side * (kHalfWidth + 0.01)}, {4.5, side * (kHalfWidth + 0.01)}, kWallLow,
               kWallHigh);
  built.slab(1.5, -kHalfWidth, 1.7, kHalfWidth, lintel_height);
  return built;
}

TEST(TraversabilityStage, ALintelLowerThanTheRobotBlocksThePassage) {
  const double below_top = testRobot().height - 0.5;
  const TraversabilityMap map = mapOf(corridorWithLintel(below_top));
  const Cell under = cellAt(map, 1.6, 0.025);
  EXPECT_EQ(under.label, CellLabel::kImpassable) << describe(under);
  EXPECT_EQ(reasonName(under.reason), "too low");
  // Beyond it the robot would fit, but cannot get there.
  const Cell beyond = cellAt(map, 3.2, 0.025);
  EXPECT_EQ(beyond.label, CellLabel::kTraversable) << describe(beyond);
  EXPECT_FALSE(beyond.reachable);
  EXPECT_GT(map.fits_not_reachable_cells, 0U);
  EXPECT_TRUE(cellAt(map, -0.5, 0.025).reachable);  // its own place
}

TEST(TraversabilityStage, ALintelWithinTheHeadroomAboveTheRobotBlocksItToo) {
  // 3 cm above the robot's top: the ground under it and the lintel are each measured to a few
  // centimetres, so the robot keeps 5 cm of headroom.
  const TraversabilityMap map = mapOf(corridorWithLintel(testRobot().height + 0.03));
  const Cell under = cellAt(map, 1.6, 0.025);
  EXPECT_EQ(under.label, CellLabel::kImpassable) << describe(under);
  EXPECT_EQ(reasonName(under.reason), "too low");
  EXPECT_FALSE(cellAt(map, 3.2, 0.025).reachable);
}

TEST(TraversabilityStage, ALintelHigherThanTheRobotLetsItPass) {
  const double above_top = testRobot().height + 0.3;
  const TraversabilityMap map = mapOf(corridorWithLintel(above_top));
  for (double x : {1.6, 3.2}) {
    const Cell cell = cellAt(map, x, 0.025);
    EXPECT_EQ(cell.label, CellLabel::kTraversable) << "at x = " << x << ": " << describe(cell);
    EXPECT_TRUE(cell.reachable) << "at x = " << x;
  }
  EXPECT_EQ(map.fits_not_reachable_cells, 0U);
}

// An open room whose floor rises at x = 2 (to x = 4.75) by `step`: ground level 1 meeting the
// reference ground there, with the riser's points measured; the robot at (-1, 0) facing +x.
constexpr double kRiserX = 1.99;  // the riser's face, in the lower floor's last cell column
HandBuiltMap stepUp(double step) {
  HandBuiltMap built(-3.0, -2.0, 5.0, 2.0);
  built.floor(-2.75, -1.75, 2.0, 1.75)
      .floor(2.0, -1.75, 4.75, 1.75, 1, step)
      .contact(0, 1, step)
      .robotAt(-1.0, 0.0, 0.0);
  built.face({kRiserX, -1.75}, {kRiserX, 1.75}, HandBuiltMap::kSampleSpacing, step);
  return built;
}

TEST(TraversabilityStage, AStepHigherThanTheRobotTakesBlocks) {
  const RobotParams robot = testRobot();
  const TraversabilityMap map = mapOf(stepUp(robot.max_step + 0.05));
  const Cell upper = cellAt(map, 3.5, 0.025);
  EXPECT_EQ(upper.label, CellLabel::kImpassable) << describe(upper);
  EXPECT_EQ(upper.reason, CellReason::kOtherLevel) << describe(upper);
  EXPECT_FALSE(upper.reachable);
  // The riser's points above the step block its cell.
  const Cell riser = cellAt(map, kRiserX, 0.025);
  EXPECT_EQ(riser.label, CellLabel::kImpassable) << describe(riser);
  EXPECT_EQ(riser.reason, CellReason::kWall) << describe(riser);
  EXPECT_EQ(map.accepted_ground, std::vector<int>{0});
}

TEST(TraversabilityStage, AStepLowerThanTheRobotTakesIsPassable) {
  const RobotParams robot = testRobot();
  const TraversabilityMap map = mapOf(stepUp(robot.max_step - 0.04));
  // The riser is a low obstacle the robot drives over: orange, not red.
  const Cell riser = cellAt(map, kRiserX, 0.025);
  EXPECT_EQ(riser.label, CellLabel::kObstacle) << describe(riser);
  EXPECT_TRUE(riser.reachable);
  const Cell upper = cellAt(map, 3.5, 0.025);
  EXPECT_EQ(upper.label, CellLabel::kTraversable) << describe(upper);
  EXPECT_TRUE(upper.reachable);
  EXPECT_EQ(map.accepted_ground, (std::vector<int>{0, 1}));
}

TEST(TraversabilityStage, AHeightJumpWithinOneGroundLevelIsTooSteepOnBothSides) {
  // One ground plane whose cells jump by more than the step (a kerb the planes did not split).
  const RobotParams robot = testRobot();
  HandBuiltMap built(-3.0, -2.0, 5.0, 2.0);
  built.floor(-2.75, -1.75, 2.0, 1.75)
      .floor(2.0, -1.75, 4.75, 1.75, 0, robot.max_step + 0.05)
      .robotAt(-1.0, 0.0, 0.0);
  const TraversabilityMap map = mapOf(built, robot);
  expectTooSteep(map, {1.975, 2.025});
  // A sharp step stands for itself: the cells farther from it than the next one keep their label
  // (a stair's first riser does not push the robot back by the step rule's run).
  expectTooSteep(map, {1.875, 1.925, 2.075, 2.125}, false);
}

// One ground level rising by `rise` from the floor (x < 2.0) to its upper part (x >= 2.1) over
// the strip of two cell columns between, where the robot does not stand (it stands at (-1, 0)).
enum class Strip {
  kUnobserved,  // no return in it: a step's edge between two scan lines
  kSpread,      // in even thirds of the rise: a step the ground triangles spread over the strip
};
HandBuiltMap riseOverTheStrip(double rise, Strip strip) {
  HandBuiltMap built(-3.0, -2.0, 5.0, 2.0);
  built.floor(-2.75, -1.75, 2.0, 1.75)
      .floor(2.1, -1.75, 4.75, 1.75, 0, rise)
      .robotAt(-1.0, 0.0, 0.0);
  if (strip == Strip::kSpread)
    built.floor(2.0, -1.75, 2.05, 1.75, 0, rise / 3).floor(2.05, -1.75, 2.1, 1.75, 0, 2 * rise / 3);
  return built;
}

class StepOverAStrip : public ::testing::TestWithParam<Strip> {};

// The step lies somewhere in an unobserved strip, perhaps right at the edge of the last lower
// cell, whose returns were then the step's face (the outdoor scene's slabs at 120 lines: the box
// stood 7 cm over a 0.13 m step); over a spread one no two cells next to each other differ by the
// step. Either way the cells either side of the strip are too steep, as if they touched.
TEST_P(StepOverAStrip, AboveTheRobotsStepTheStripsEdgesAreTooSteep) {
  const RobotParams robot = testRobot();
  const TraversabilityMap map = mapOf(riseOverTheStrip(robot.max_step + 0.02, GetParam()), robot);
  expectTooSteep(map, {1.975, 2.125});
  // One cell farther in, the box no longer covers the edge cell's centre: green again.
  const Cell inside = cellAt(map, 1.475, 0.025);
  EXPECT_EQ(inside.label, CellLabel::kTraversable) << describe(inside);
}

TEST_P(StepOverAStrip, WithinTheRobotsStepNothingIsTooSteep) {
  const RobotParams robot = testRobot();
  expectTooSteep(mapOf(riseOverTheStrip(robot.max_step - 0.02, GetParam()), robot),
                 {1.975, 2.025, 2.075, 2.125}, false);
}

INSTANTIATE_TEST_SUITE_P(UnobservedOrSpread, StepOverAStrip,
                         ::testing::Values(Strip::kUnobserved, Strip::kSpread));

// A ramp steep enough (35 deg) to rise by more than the step across the strip: its slope explains
// the rise, which is no step.
TEST(TraversabilityStage, ARampsRiseAcrossAnUnobservedGapIsNoStep) {
  const RobotParams robot = testRobot();
  const double slope = std::tan(35.0 * std::numbers::pi / 180);
  ASSERT_GT(slope * 0.15, robot.max_step);  // the rise between the strip's two edge cells
  HandBuiltMap built(-3.0, -2.0, 5.0, 2.0);
  built.ramp(-2.75, -1.75, 2.0, 1.75, 0, slope)
      .ramp(2.1, -1.75, 4.75, 1.75, 0, slope)
      .robotAt(-1.0, 0.0, 0.0);
  expectTooSteep(mapOf(built, robot), {1.975, 2.125}, false);
}

// Ground up to the grid's edge (a multi-beam map cut at its vouched range has no unobserved rim):
// what lies beyond the map was not seen, so a box that would stick out of it does not fit there.
TEST(TraversabilityStage, ABoxStickingOutOfTheMapDoesNotFit) {
  constexpr double kEdge = 3.0;
  const RobotParams robot = testRobot();
  HandBuiltMap built(-kEdge, -kEdge, kEdge, kEdge);
  built.floor(-kEdge, -kEdge, kEdge, kEdge).robotAt(0.0, 0.0, 0.0);
  const TraversabilityMap map = mapOf(built, robot);
  // Half the robot's width is the least any orientation leaves between its centre and the edge.
  // Careful (exact) fits may move the centre within its cell, and the unobserved outside blocks
  // at its cells' centres, as unobserved cells do everywhere: a cell of slack for orange.
  const double inscribed = robot.width / 2;
  std::size_t near_edge = 0;
  for (int row = 0; row < map.grid.height; ++row)
    for (int column = 0; column < map.grid.width; ++column) {
      const Eigen::Vector2d centre = map.grid.centre(column, row);
      const double to_edge = kEdge - centre.cwiseAbs().maxCoeff();
      if (to_edge >= inscribed) continue;
      ++near_edge;
      const auto label = CellLabel(map.labels[map.grid.index(column, row)]);
      EXPECT_NE(label, CellLabel::kTraversable)
          << "the box sticks out of the map at " << centre.transpose() << " yet shows green";
      if (to_edge < inscribed - map.grid.resolution) {
        EXPECT_NE(label, CellLabel::kCareful)
            << "the box sticks out of the map at " << centre.transpose() << " yet shows orange";
      }
    }
  EXPECT_GT(near_edge, 0U);
  EXPECT_GT(map.counts[std::size_t(CellLabel::kTraversable)], 0U);  // the middle is open floor
}

TEST(TraversabilityStage, AnOpenFloorIsGreenWhereverTheBoxFitsAndReachable) {
  constexpr double kFloorEdge = 2.5;  // floor over [-2.5, 2.5]^2, grid over [-3, 3]^2
  const RobotParams robot = testRobot();
  HandBuiltMap built(-3.0, -3.0, 3.0, 3.0);
  built.floor(-kFloorEdge, -kFloorEdge, kFloorEdge, kFloorEdge).robotAt(0.3, -0.2, 0.4);
  const TraversabilityMap map = mapOf(built, robot);
  // The box fits in every orientation where the floor reaches past its half diagonal.
  const double fits_within = kFloorEdge - std::hypot(robot.length / 2, robot.width / 2) - 0.05;
  std::size_t inside = 0;
  for (int row = 0; row < map.grid.height; ++row)
    for (int column = 0; column < map.grid.width; ++column) {
      const Eigen::Vector2d centre = map.grid.centre(column, row);
      const std::size_t i = map.grid.index(column, row);
      const auto label = CellLabel(map.labels[i]);
      EXPECT_NE(label, CellLabel::kObstacle) << centre.transpose();
      // Near the floor's edge the box fits with little margin (careful) or not at all.
      if (label == CellLabel::kTraversable || label == CellLabel::kCareful) {
        EXPECT_TRUE(map.reach[i]) << "fits but unreachable at " << centre.transpose();
      }
      if (label == CellLabel::kImpassable) {
        EXPECT_EQ(CellReason(map.reasons[i]), CellReason::kTooNarrow) << centre.transpose();
      }
      if (centre.cwiseAbs().maxCoeff() > fits_within) continue;
      ++inside;
      EXPECT_EQ(label, CellLabel::kTraversable) << centre.transpose();
    }
  EXPECT_GT(inside, 0U);
  EXPECT_EQ(map.counts[std::size_t(CellLabel::kTraversable)] +
                map.counts[std::size_t(CellLabel::kCareful)],
            map.reachable_cells);
  EXPECT_EQ(map.fits_not_reachable_cells, 0U);
  // The robot's own cells are green and reachable.
  const Cell own = cellAt(map, 0.3, -0.2);
  EXPECT_EQ(own.label, CellLabel::kTraversable);
  EXPECT_TRUE(own.reachable);
  EXPECT_NEAR(map.robot_pose.x, 0.3, 1e-9);
  EXPECT_NEAR(map.robot_pose.yaw, 0.4, 1e-9);
}

// Without a recorded pose the robot stands where its box, holding the scanner's foot (the map's
// origin), holds no blocking return: a wall beside the scanner pushes it to the other side, in
// whichever direction the wall lies, and a box that fits stays at the mounting's offset.
TEST(TraversabilityStage, WithoutARecordedPoseTheRobotStandsClearOfAWallBesideTheScanner) {
  const RobotParams robot = testRobot();
  struct Wall {
    Eigen::Vector2d from, to;
    Eigen::Vector2d away;  // the side of the scanner the box must move to
  };
  const Wall walls[] = {{{-3.0, 0.3}, {3.0, 0.3}, {0.0, -1.0}},
                        {{-3.0, -0.3}, {3.0, -0.3}, {0.0, 1.0}},
                        {{0.35, -3.0}, {0.35, 3.0}, {-1.0, 0.0}},
                        {{-0.35, -3.0}, {-0.35, 3.0}, {1.0, 0.0}}};
  for (const Wall& wall : walls) {
    HandBuiltMap built(-4.0, -4.0, 4.0, 4.0);
    built.floor(-3.5, -3.5, 3.5, 3.5).face(wall.from, wall.to, kWallLow, kWallHigh);
    const RobotPose pose = robotPoseOnMap(built.analysis(), robot, {0.0, std::numbers::pi / 2});
    const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
    auto inBox = [&](const Eigen::Vector2d& p) {
      const Eigen::Vector2d d = p - Eigen::Vector2d(pose.x, pose.y);
      return std::abs(d.x() * c + d.y() * s) <= robot.length / 2 + 1e-9 &&
             std::abs(-d.x() * s + d.y() * c) <= robot.width / 2 + 1e-9;
    };
    const std::string where =
        "wall from " + std::to_string(wall.from.x()) + ", " + std::to_string(wall.from.y());
    EXPECT_TRUE(inBox(Eigen::Vector2d::Zero())) << where << ": the scanner's foot is off the box";
    for (const MapObstacle& o : built.analysis().inputs.obstacles)
      ASSERT_FALSE(inBox({o.x, o.y}))
          << where << ": a wall return at " << o.x << ", " << o.y << " is inside the box";
    EXPECT_GT(Eigen::Vector2d(pose.x, pose.y).dot(wall.away), 0.0) << where;
  }
  // Nothing near: the box stays where the mounting puts it.
  HandBuiltMap open(-4.0, -4.0, 4.0, 4.0);
  open.floor(-3.5, -3.5, 3.5, 3.5);
  const RobotPose pose = robotPoseOnMap(open.analysis(), robot, {0.0, std::numbers::pi / 2});
  EXPECT_NEAR(pose.x, -robot.mount_x, 1e-9);
  EXPECT_NEAR(pose.y, -robot.mount_y, 1e-9);
}

}  // namespace
}  // namespace clearway
