#pragma once

// The robot's box on the map grid (paper II-D): the orientations tried, the box's cells in each
// (footprints), and the two tests of one pose (a cell and an orientation) that the label loop and
// the reachability search share: the coarse test of the enlarged box against blocked cell centres
// (green) and the exact test of the nominal box against the measured points (orange).

#include <array>
#include <atomic>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "cell_classes.h"
#include "clearway/segmentation/params.h"
#include "clearway/segmentation/scan_analysis.h"
#include "clearway/traversability/reachability.h"

namespace clearway::detail {

// Margins of the footprints, in cells (the map's resolution).
// The coarse test's box is the nominal one grown by half a cell on every side: a cell that passes
// it keeps that much room whatever its points do (green, not orange).
inline constexpr double kGreenMarginCells = 0.5;
// The core is the nominal box shrunk by this: a blocked cell centre in there blocks the robot
// wherever its centre is in its cell (0.4 cells) and wherever the cell's points are (0.71 cells).
inline constexpr double kCoreInsetCells = 1.2;
// A cell's points lie within half a diagonal (0.71 cells) of its centre, and the exact test moves
// the robot's centre up to 0.4 cells along each axis: every cell within this of the box may matter.
inline constexpr double kRimReachCells = 1.3;
// A blocked cell's points lie up to 0.71 cells beyond its centre and the robot's centre moves up
// to 0.57 cells in its cell: with a clearance below inradius - 1.28 cells no position can fit, so
// the exact test is not even tried (0.02 for rounding).
inline constexpr float kExactTestSlackCells = 1.3F;

// The exact test tries the robot's centre at this many positions along each of the box's axes,
// a fifth of a cell apart (the paper's finer discretisation).
inline constexpr int kExactCentresPerAxis = 5;
// How far inside the box, beyond the reach of the exact test's centres, a cell centre must lie to
// count as deep (Footprints::deep) [cells]: far above rounding, far below any distance that
// matters.
inline constexpr double kDeepSlackCells = 1e-6;

// Orientations closer than this are one [rad].
inline constexpr double kSameYaw = 1e-2;
// Orientation indices are stored in bytes (TraversabilityMap::orientation); kNoOrientation
// (traversability_map.h) marks a cell where nothing fits, and the list stops well below it.
inline constexpr std::size_t kMaxOrientations = 250;
// A wall plane whose normal's horizontal part is at least this long stands (tilted less than
// about 45 deg from vertical): its direction is worth trying as an orientation.
inline constexpr double kStandingWallNormal = 0.7;

// Index of `yaw` (modulo 180 deg) in `yaws`, appended when new; -1 when the list is full.
int orientationIndex(std::vector<double>& yaws, double yaw);

// Uniform orientations plus, for every wall, its own direction and the one square to it.
std::vector<double> orientationsToTry(const ScanAnalysis& analysis, int uniform);

struct Offset {
  int dx, dy;
  float radius;  // cells
};

// The cells dx = first..last of row dy (offsets from the box's cell).
struct RowSpan {
  int dy, first, last;
};

struct Footprints {
  // Per orientation, row by row (a test of either is then one look per row, not per cell):
  std::vector<std::vector<RowSpan>> enlarged;  // nominal + kGreenMarginCells on every side
  // Nominal less kCoreInsetCells on every side: blocks wherever it holds something that blocks.
  std::vector<std::vector<RowSpan>> core;
  // Cells whose centres lie inside the nominal box wherever the exact test puts the robot's
  // centre in its cell: an unobserved or blocked cell with no points there blocks every position.
  std::vector<std::vector<RowSpan>> deep;
  // Every cell that may hold a point inside the box, less the core (the exact check has cleared
  // the core before it looks at these).
  std::vector<std::vector<Offset>> rim;
  std::vector<double> yaw;
  double inner_radius = 0.0;  // cells: inside this the box is blocked in every orientation
  double outer_radius = 0.0;  // cells: beyond this nothing can touch the enlarged box
};

// The rim's offsets sorted by radius, nearest first.
Footprints makeFootprints(const RobotParams& robot, double resolution,
                          const std::vector<double>& yaws, int threads);

// Unobserved cells the careful check tolerates (1, else 0): single-cell gaps between observed
// cells on two opposite sides, with no blocked cell around them (a gap between scan lines in the
// open). Not a gap beside a blocked cell (the obstacle's edge may lie in it: where two paving
// slabs meet with a step, the first blocking returns were 10 cm in from the edge and the box
// reached over the gap), not the open edge of the observed space (past an invisible glass wall,
// over an unseen drop), not a wider unobserved strip (a thin wall seen end-on), and not the inside
// of an obstacle between its sparse points.
std::vector<std::uint8_t> toleratedUnknownCells(const CellClasses& classes, const MapGrid& grid);

// Unobserved cells an edge of the ground may cross anywhere (1, else 0), which the exact test
// therefore takes as a whole, not by their centre:
// - beside a drop (ground too steep or of another level: a pit's far wall, a dock's edge);
// - where the ground ends along the scanner's rays: the cell's neighbour towards the scanner is
//   free, and beyond the cell, along the ray, the first cell seen within `reach` cells is a drop,
//   or none is (a pit's near rim, whose wall the rays cannot see). A gap between the samples of
//   one floor has that floor again beyond it and keeps its centre rule.
std::vector<std::uint8_t> unknownCellsAnEdgeMayCross(const CellClasses& classes,
                                                     const MapGrid& grid, int reach);

// Cells whose box tests read nothing that sparse cells change (0), else 1: beyond the box's reach
// with the exact test's rim, plus the reach of the tolerated-unknown rule's closing, from every
// sparse cell. There the placement with sparse cells blocked tests exactly as the one without.
std::vector<std::uint8_t> cellsNearSparse(const std::vector<std::uint8_t>& sparse,
                                          const MapGrid& grid, const Footprints& footprints);

// Within the inscribed radius (plus the coarse test's margin) something blocks the enlarged box in
// every orientation; below inradius - kExactTestSlackCells the exact test cannot pass.
struct TestRadii {
  double coarse, exact;
  explicit TestRadii(const Footprints& footprints)
      : coarse(footprints.inner_radius + kGreenMarginCells),
        exact(footprints.inner_radius - kExactTestSlackCells) {}
};

// The two tests of one pose, callable from several threads at once.
class FootprintTester {
 public:
  FootprintTester(const MapGrid& grid, const CellClasses& classes,
                  const std::vector<std::uint8_t>& tolerated, const Footprints& footprints,
                  const RobotParams& robot, int threads = 1);

  // Distance (in cells) from the cell's centre to the nearest centre of a cell that blocks, exact
  // (distance_field.h) less a rounding margin: strictly (unobserved blocks) and leniently
  // (tolerated unobserved cells do not). Every use skips only tests whose outcome it is sure of.
  float clearance(int column, int row) const { return clearance_[index(column, row)]; }
  float lenientClearance(int column, int row) const {
    return lenient_clearance_[index(column, row)];
  }

  // Coarse test of the enlarged box: no blocked cell centre inside it.
  bool fitsEnlarged(int column, int row, int orientation) const;

  // Exact test of the nominal box: no measured point inside it, and no centre of an unobserved,
  // unreachable or stepped cell. The paper's finer discretisation: the robot's centre may be
  // anywhere in the cell, tried at 5 x 5 positions a fifth of a cell apart, centre first.
  bool fitsExactlyInCell(int column, int row, int orientation) const;

 private:
  // The 5 x 5 centres of the exact test, in the order tried.
  static constexpr int kCentresPerAxis = kExactCentresPerAxis;
  static constexpr int kCentres = kCentresPerAxis * kCentresPerAxis;
  // Per orientation, what the exact test needs, computed once.
  struct Turn {
    double c = 1.0, s = 0.0;  // cos and sin of the yaw
    double shift = 0.0;       // how far the 25 centres reach along u and along v [m]
    std::array<double, kCentres> du{}, dv{};  // the centres in the box's frame [m]
  };
  // Bounds of one cell's blocking points (map frame, metres).
  struct PointBounds {
    double min_x, max_x, min_y, max_y;
  };
  // A cell's points that lie farthest along -u, +u, -v and +v of one orientation (indices into
  // CellClasses::xs/ys), kSeveral where two points come within kTieTolerance of the extreme.
  enum Extreme { kLeastU, kMostU, kLeastV, kMostV };
  using Extremes = std::array<std::uint32_t, 4>;
  static constexpr std::uint32_t kSeveral = std::numeric_limits<std::uint32_t>::max();
  static constexpr std::uint32_t kNoPoints = std::numeric_limits<std::uint32_t>::max();

  // The extremes of `cell`'s points in orientation k, worked out on first use (by one thread;
  // nullptr while another one is at it).
  const Extremes* extremes(std::size_t cell, std::size_t k) const;
  // Adds what `cell`'s points contribute to the exact test at a box centred `centre` in
  // orientation k, through `add(x, y)`; false when they block every centre of the test.
  template <typename Add>
  bool addCellPoints(std::size_t cell, std::size_t k, const Eigen::Vector2d& centre,
                     Add&& add) const;

  std::size_t index(int column, int row) const {
    return std::size_t(row) * std::size_t(grid_.width) + std::size_t(column);
  }
  std::size_t paddedIndex(int column, int row) const {
    return std::size_t(row + pad_) * std::size_t(stride_) + std::size_t(column + pad_);
  }

  const MapGrid& grid_;
  const CellClasses& classes_;
  const Footprints& footprints_;
  double half_length_ = 0.0, half_width_ = 0.0;  // the nominal box [m]
  double step_ = 0.0;                            // between the exact test's centres [m]
  std::vector<float> clearance_, lenient_clearance_;
  int pad_ = 0;
  int stride_ = 0;
  // One byte per cell, so each offset costs one read: strict (blocked or unobserved) and lenient
  // (the codes below). A border as wide as the largest footprint stands for the outside of the
  // map, which blocks: no bounds checks.
  static constexpr std::uint8_t kPassable = 0;
  // Blocked by measured points only: the exact test reads the points.
  static constexpr std::uint8_t kBlockedByPoints = 1;
  // Blocked otherwise, unobserved (and not a gap a beam fell through), or outside the map: blocks
  // at its centre. The samples either side of an unobserved stretch leave off about where its
  // cells begin: a door's jamb casts one, and a door 5 cm wider than the robot is passed.
  static constexpr std::uint8_t kBlockedAtCentre = 2;
  // Unobserved where an edge of the ground may cross it (unknownCellsAnEdgeMayCross: beside a
  // drop, or where the ground ends along the rays): the edge may lie anywhere in it, and all of it
  // blocks.
  static constexpr std::uint8_t kBlockedWhole = 3;
  std::vector<std::uint8_t> strict_;   // padded
  std::vector<std::uint8_t> lenient_;  // padded
  // Per cell: its number among the cells with blocking points (else kNoPoints). Those cells'
  // bounds, and their slots of orientations in extremes_ (number * orientations + k).
  std::vector<std::uint32_t> point_cell_;
  std::vector<PointBounds> point_bounds_;
  mutable std::unique_ptr<Extremes[]> extremes_;
  enum SlotState : std::uint8_t { kSlotEmpty, kSlotFilling, kSlotReady };
  mutable std::unique_ptr<std::atomic<std::uint8_t>[]> slot_state_;
  // Per orientation, the rim's offsets as steps in the padded arrays.
  std::vector<std::vector<std::ptrdiff_t>> rim_;
  // Per padded row, a running count (modulo 2^16) of the cells that block strictly / leniently,
  // one more entry than the row has cells: a stretch of a row holds a blocking cell exactly when
  // the counts at its two ends differ (a stretch is shorter than 2^16 cells).
  std::vector<std::uint16_t> strict_counts_, lenient_counts_;
  // The same of the cells that block by their centre (lenient code 2: unobserved, or blocked with
  // no points), for the deep test.
  std::vector<std::uint16_t> centre_counts_;
  // A footprint's cells in one row, as the two ends of that stretch relative to the cell's own
  // entry in the running counts.
  struct Run {
    std::ptrdiff_t start, end;
  };
  // Per orientation, the enlarged box, the core and the deep cells as runs: a test of any is one
  // look at each of its rows, not at each of its cells.
  std::vector<std::vector<Run>> enlarged_runs_, core_runs_, deep_runs_;
  std::size_t countsIndex(int column, int row) const {
    return std::size_t(row + pad_) * std::size_t(stride_ + 1) + std::size_t(column + pad_);
  }
  // Whether any cell of `runs` around (column, row) blocks, by `counts`.
  bool holdsBlocking(const std::vector<std::uint16_t>& counts, const std::vector<Run>& runs,
                     int column, int row) const {
    const std::uint16_t* here = counts.data() + countsIndex(column, row);
    for (const Run& run : runs)
      if (here[run.end] != here[run.start]) return true;
    return false;
  }
  std::vector<Turn> turns_;
};

// One pose's fit as the placement tests it: green where the coarse test passes (tried where the
// clearance lets it), careful where only the exact test does (where the lenient clearance lets it).
// Inline: completeFits calls it for every pose the label loop did not test.
inline PoseFit testPose(const FootprintTester& tester, const TestRadii& radii, int column, int row,
                        int orientation) {
  if (tester.clearance(column, row) >= radii.coarse &&
      tester.fitsEnlarged(column, row, orientation))
    return PoseFit::kClear;
  if (tester.lenientClearance(column, row) >= radii.exact &&
      tester.fitsExactlyInCell(column, row, orientation))
    return PoseFit::kCareful;
  return PoseFit::kBlocked;
}

}  // namespace clearway::detail
