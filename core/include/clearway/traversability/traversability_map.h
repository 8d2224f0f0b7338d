#pragma once

// Stage 5 (paper II-D): where the robot's centre can be, for one robot size. Labels and their
// values are those of labels.pgm (docs/FORMATS.md).

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "clearway/progress.h"
#include "clearway/segmentation/params.h"
#include "clearway/segmentation/scan_analysis.h"
#include "clearway/traversability/reachability.h"

namespace clearway {

enum class CellLabel : std::uint8_t {
  kUnknown = 0,      // not observed
  kTraversable = 1,  // green
  kCareful = 2,      // orange: fits only with little margin (narrow passage)
  kObstacle = 3,     // orange: a low, probably passable obstacle, or too sparse to be sure
  kImpassable = 4,   // red
  kStairs = 5,       // stairs the robot can climb, with care (else impassable, kStairsTooSteep)
};
inline constexpr int kCellLabelCount = 6;
// The robot's box fits on such a cell (green or orange): traversable, careful, or probably
// passable (a low obstacle, or ground too sparse to vouch for).
inline bool robotFits(CellLabel label) {
  return label == CellLabel::kTraversable || label == CellLabel::kCareful ||
         label == CellLabel::kObstacle;
}
// A cell the map tells the operator the robot may drive on: where it fits, and stairs it can
// climb. All withheld where the result rests on an up direction nobody confirmed.
inline bool drivable(CellLabel label) {
  return robotFits(label) || label == CellLabel::kStairs;
}
// TraversabilityMap::orientation of a cell where no orientation fits (orientations are bytes).
inline constexpr std::uint8_t kNoOrientation = 255;

// Why a cell is red (or why the robot cannot stand there).
enum class CellReason : std::uint8_t {
  kNone = 0,
  kWall = 1,            // something stands in the way from the ground up
  kTooLow = 2,          // an overhang lower than the robot
  kTooSteep = 3,        // a step or drop higher than the robot can take
  kTooNarrow = 4,       // free, but something seen keeps the robot's box out in every orientation
  kOtherLevel = 5,      // a surface the robot cannot reach (a table top, a platform)
  kStairsTooSteep = 6,  // stairs whose risers or flight are steeper than the robot climbs
  // Orange, not green: the ground samples under the robot's box are so far apart that an obstacle
  // taller than the robot's step could stand between them unseen.
  kSparse = 7,
  // Grey, not red: ground was seen here, but the robot's box fits in no orientation only because
  // the cells around it were not seen (no blocking cell within the box's reach): nothing seen
  // stops the robot, and nothing vouches for it.
  kUnseenAround = 8,
  // Orange, not green: the robot fits, but its band up to its height was above everything the
  // scanner looked at there (a turntable axis pointing down sees nothing above the scanner): an
  // overhang could stand there unmeasured.
  kAboveView = 9,
};
std::string_view reasonName(CellReason reason);
std::string_view labelName(CellLabel label);

struct TraversabilityMap {
  MapGrid grid;
  std::vector<std::uint8_t> labels;   // CellLabel per cell; row 0 = smallest map y
  std::vector<std::uint8_t> reasons;  // CellReason per cell
  // Index into `yaws` of an orientation the robot fits in, 255 if none.
  std::vector<std::uint8_t> orientation;
  // Orientations tried [rad, map frame]: uniform over 180 deg, plus those of the walls (doors are
  // in walls, and a narrow door is only passable square to its wall).
  std::vector<double> yaws;
  std::array<std::size_t, kCellLabelCount> counts{};
  std::vector<int> accepted_ground;  // ground planes the robot can reach from the reference

  // Where the robot stands (its own cells are ground: it stands on them) and where it can get.
  RobotPose robot_pose;
  int robot_orientation = -1;  // index into yaws of the robot's own heading
  // A recorded pose gave the heading; without one it is a guess, and the robot may stand in any
  // orientation its box fits in at its own place.
  bool robot_heading_known = false;
  std::vector<std::uint8_t> reach;  // per cell: 1 reachable from the robot's pose, else 0
  std::size_t reachable_cells = 0;
  std::size_t fits_not_reachable_cells = 0;  // green/orange cells the robot cannot get to
  // Why the reach stops short, in words (empty unless the robot fits in more cells it cannot get
  // to than it reaches): unobserved ground around it, or what shuts it in.
  std::string reach_limit;
  // The fit of every pose the reachability search met, so a goal query finds every reachable
  // pose's fit here (kUntested elsewhere).
  MetPoseFits pose_fit;

  CellLabel label(int column, int row) const { return CellLabel(labels[grid.index(column, row)]); }
  double yawDegrees(int column, int row) const;  // NaN where nothing fits
};

// Builds the map for `robot` from a scan analysis; cheap enough to re-run on every slider move.
// With no trusted ground the map has no traversable cell.
TraversabilityMap computeTraversability(const ScanAnalysis& analysis, const RobotParams& robot,
                                        const MapParams& params, int threads = 2,
                                        const ProgressCallback& progress = {});

}  // namespace clearway
