// Which unobserved cells the exact test takes as a whole (unknownCellsAnEdgeMayCross): beside a
// drop, and where the ground ends along the scanner's rays, on cell classes built by hand. A
// failure here is that rule's, not the segmentation's or the placement's.

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "../../../core/src/traversability/cell_classes.h"
#include "../../../core/src/traversability/footprints.h"

namespace clearway {
namespace {

using detail::CellClasses;
using detail::CellState;

// One row of cells along x, 5 cm each, from x = 0: its states given as characters, 'g' ground,
// '.' unobserved, 'd' ground of another level (a drop), 'w' a wall; the scanner at `viewpoint_x`
// on the row's line. Rows above and below are unobserved, so every cell has neighbours.
struct Row {
  MapGrid grid;
  CellClasses classes;

  Row(const char* cells, double viewpoint_x) {
    const auto width = int(std::char_traits<char>::length(cells));
    grid.resolution = 0.05;
    grid.origin = {0.0, -0.075};
    grid.width = width;
    grid.height = 3;
    classes.state.assign(grid.cells(), CellState::kUnknown);
    classes.reason.assign(grid.cells(), CellReason::kNone);
    for (int column = 0; column < width; ++column) {
      const std::size_t cell = grid.index(column, 1);
      switch (cells[column]) {
        case 'g':
          classes.state[cell] = CellState::kGround;
          break;
        case 'd':
          classes.state[cell] = CellState::kBlocked;
          classes.reason[cell] = CellReason::kOtherLevel;
          break;
        case 'w':
          classes.state[cell] = CellState::kBlocked;
          classes.reason[cell] = CellReason::kWall;
          break;
        default:
          break;
      }
    }
    classes.viewpoint = {viewpoint_x, 0.0};
  }

  // The marks along the middle row: 'X' taken as a whole, '-' not.
  std::string marks(int reach) const {
    const std::vector<std::uint8_t> crossed =
        detail::unknownCellsAnEdgeMayCross(classes, grid, reach);
    std::string out;
    for (int column = 0; column < grid.width; ++column)
      out += crossed[grid.index(column, 1)] ? 'X' : '-';
    return out;
  }
};

constexpr int kReach = 8;  // cells: the box's outer radius in the tester

TEST(UnknownCellsAnEdgeMayCross, TheFirstUnseenCellPastTheGroundBeforeADropIsTakenWhole) {
  // The scanner on the left: a rim at x = 0.3 m, the drop's floor seen from x = 0.5 m.
  const Row row("gggggg....dddd", 0.0);
  // The cell past the last ground, and the one beside the drop; not the ones between.
  EXPECT_EQ(row.marks(kReach), "------X--X----");
}

TEST(UnknownCellsAnEdgeMayCross, AGapInOneFloorKeepsItsCentreRule) {
  const Row row("gggggg....gggg", 0.0);
  EXPECT_EQ(row.marks(kReach), "--------------");
}

TEST(UnknownCellsAnEdgeMayCross, GroundEndingWithNothingSeenBeyondIsTakenWhole) {
  // Nothing within reach beyond: a ledge whose lower floor was not seen.
  const Row row("gggggg..........", 0.0);
  EXPECT_EQ(row.marks(kReach), "------X---------");
  // The lower floor seen beyond the reach counts as nothing seen.
  const Row far("gggggg..........dd", 0.0);
  EXPECT_EQ(far.marks(kReach), "------X--------X--");
}

TEST(UnknownCellsAnEdgeMayCross, AWallBeyondTheGapIsNoDrop) {
  // The foot of a wall the rays met after a gap: the gap keeps its centre rule.
  const Row row("gggggg...wwww", 0.0);
  EXPECT_EQ(row.marks(kReach), "-------------");
}

TEST(UnknownCellsAnEdgeMayCross, OnlyTheSideFacingAwayFromTheScannerIsAnEnd) {
  // The scanner on the right: the ground's end towards it is where the rays arrive, not leave.
  const Row row("dddd....gggggg", 0.7);
  EXPECT_EQ(row.marks(kReach), "----X--X------");
  const Row gap("....gggggg", 0.5);
  EXPECT_EQ(gap.marks(kReach), "---X------");
}

TEST(UnknownCellsAnEdgeMayCross, TheRobotsOwnPlaceIsNoGroundTheRaysPassedOver) {
  // Ground made so because the robot stands there, seen or not: the scanner's blind zone around
  // it is no ledge (counted, it walled the robot in on Hannover scan440).
  Row row("gggggg........", 0.0);
  row.classes.own_place.assign(row.grid.cells(), 0);
  for (int column = 0; column < 6; ++column)
    row.classes.own_place[row.grid.index(column, 1)] = 1;
  EXPECT_EQ(row.marks(kReach), "--------------");
}

TEST(UnknownCellsAnEdgeMayCross, ObservedCellsAreNeverMarked) {
  // A drop's own cells and the ground beside it are observed: the exact test reads them as they
  // are.
  const Row row("ggggdddd", 0.0);
  EXPECT_EQ(row.marks(kReach), "--------");
}

}  // namespace
}  // namespace clearway
