// The traversability stage's shortcuts change no answer: its label map, reach layer and the fit
// of every pose the reachability search visits equal those of a plain reference written here,
// which tests every (cell, orientation) pose by the paper's definitions (paper II-D, as
// docs/ALGORITHM.md states them) with no clearance shortcut, no footprint list sorted by radius,
// no cache and no parallel ring, and searches with a plain breadth-first search. Scenes of the
// peers table, simulated small so that the test runs fast in Debug and under the sanitizers.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <numbers>
#include <numeric>

#include "../../../core/src/traversability/cell_classes.h"
#include "../../../core/src/traversability/footprints.h"
#include "../../../core/src/traversability/motion_primitives.h"
#include "../../../core/src/traversability/unseen_surroundings.h"
#include "../../../core/src/traversability/view_band.h"
#include "clearway/segmentation/stairs.h"
#include "engine_fixtures.h"

namespace clearway {
namespace {

using detail::CellClasses;
using detail::CellState;

bool fitsLabel(std::uint8_t label) {
  return label == std::uint8_t(CellLabel::kTraversable) ||
         label == std::uint8_t(CellLabel::kCareful) || label == std::uint8_t(CellLabel::kObstacle);
}

// The two tests of one pose, spelt out: every cell of a window around the box is looked at.
class PlainPoseTests {
 public:
  PlainPoseTests(const MapGrid& grid, const CellClasses& classes, const RobotParams& robot,
                 const std::vector<double>& yaws)
      : grid_(grid),
        classes_(classes),
        tolerated_(detail::toleratedUnknownCells(classes, grid)),
        yaws_(yaws),
        along_(robot.length / 2 / grid.resolution),
        across_(robot.width / 2 / grid.resolution),
        half_length_(robot.length / 2),
        half_width_(robot.width / 2),
        window_(int(std::ceil(std::hypot(along_ + detail::kRimReachCells,
                                         across_ + detail::kRimReachCells))) +
                1),
        footprints_(detail::makeFootprints(robot, grid.resolution, yaws, 1)),
        gates_(grid, classes, tolerated_, footprints_, robot),
        edge_may_cross_(detail::unknownCellsAnEdgeMayCross(
            classes, grid, int(std::ceil(footprints_.outer_radius)))),
        inner_radius_(footprints_.inner_radius) {}

  // Blocked or unobserved, and everything outside the map.
  bool strictlyBlocked(int column, int row) const {
    if (!grid_.inside(column, row)) return true;
    const CellState state = classes_.state[grid_.index(column, row)];
    return state == CellState::kBlocked || state == CellState::kUnknown;
  }
  // 0 passable, 1 blocked by measured points only, 2 blocking at its centre (blocked otherwise,
  // unobserved, outside the map), 3 blocking as a whole (unobserved where an edge of the ground
  // may cross it).
  int lenientCode(int column, int row) const {
    if (!grid_.inside(column, row)) return 2;
    const std::size_t cell = grid_.index(column, row);
    switch (classes_.state[cell]) {
      case CellState::kBlocked:
        return classes_.blocked_by_points_only[cell] ? 1 : 2;
      case CellState::kUnknown:
        return tolerated_[cell] ? 0 : edge_may_cross_[cell] ? 3 : 2;
      default:
        return 0;
    }
  }

  // No strictly blocked cell centre in the box grown by half a cell.
  bool enlargedFits(int column, int row, int k) const {
    const double c = std::cos(yaws_[std::size_t(k)]), s = std::sin(yaws_[std::size_t(k)]);
    for (int dy = -window_; dy <= window_; ++dy)
      for (int dx = -window_; dx <= window_; ++dx)
        if (std::abs(dx * c + dy * s) <= along_ + detail::kGreenMarginCells &&
            std::abs(-dx * s + dy * c) <= across_ + detail::kGreenMarginCells &&
            strictlyBlocked(column + dx, row + dy))
          return false;
    return true;
  }

  // Nothing blocking with its centre deep inside the box (the core), and at one of the 5 x 5
  // centres a fifth of a cell apart no measured point and no other blocking cell's centre inside
  // the nominal box.
  bool exactFits(int column, int row, int k) const {
    const double c = std::cos(yaws_[std::size_t(k)]), s = std::sin(yaws_[std::size_t(k)]);
    const double core_along = std::max(0.0, along_ - detail::kCoreInsetCells);
    const double core_across = std::max(0.0, across_ - detail::kCoreInsetCells);
    const Eigen::Vector2d centre = grid_.centre(column, row);
    std::vector<Eigen::Vector2d> items;  // in the box's frame, from the cell's centre [m]
    auto add = [&](double x, double y) {
      const double dx = x - centre.x(), dy = y - centre.y();
      items.emplace_back(dx * c + dy * s, -dx * s + dy * c);
    };
    for (int dy = -window_; dy <= window_; ++dy)
      for (int dx = -window_; dx <= window_; ++dx) {
        const int code = lenientCode(column + dx, row + dy);
        if (code == 0) continue;
        if (std::abs(dx * c + dy * s) <= core_along && std::abs(-dx * s + dy * c) <= core_across)
          return false;
        if (code == 1) {
          const std::size_t cell = grid_.index(column + dx, row + dy);
          for (std::uint32_t p = classes_.point_start[cell]; p < classes_.point_start[cell + 1];
               ++p)
            add(classes_.xs[p], classes_.ys[p]);
        } else if (code == 2) {
          const Eigen::Vector2d other = grid_.centre(column + dx, row + dy);
          add(other.x(), other.y());
        } else {
          const Eigen::Vector2d other = grid_.centre(column + dx, row + dy);
          for (const double cx : {-0.5, 0.5})
            for (const double cy : {-0.5, 0.5})
              add(other.x() + cx * grid_.resolution, other.y() + cy * grid_.resolution);
        }
      }
    const double step = grid_.resolution / 5.0;
    for (int sy = -2; sy <= 2; ++sy)
      for (int sx = -2; sx <= 2; ++sx) {
        const double du = (sx * c + sy * s) * step, dv = (-sx * s + sy * c) * step;
        const bool clear = std::none_of(items.begin(), items.end(), [&](const Eigen::Vector2d& i) {
          return std::abs(i.x() - du) < half_length_ && std::abs(i.y() - dv) < half_width_;
        });
        if (clear) return true;
      }
    return false;
  }

  // The stage tries the coarse test only where the clearance reaches past the inscribed circle
  // (plus the half cell), and the exact test only where the lenient clearance leaves room for it
  // (kExactTestSlackCells): that is part of its definition (nearer, a cell is orange or too
  // narrow), not a shortcut, so the reference gates its tests the same way, with the same
  // distance transform.
  PoseFit fit(int column, int row, int k) const {
    if (gates_.clearance(column, row) >= inner_radius_ + detail::kGreenMarginCells &&
        enlargedFits(column, row, k))
      return PoseFit::kClear;
    if (gates_.lenientClearance(column, row) >= inner_radius_ - detail::kExactTestSlackCells &&
        exactFits(column, row, k))
      return PoseFit::kCareful;
    return PoseFit::kBlocked;
  }

 private:
  const MapGrid& grid_;
  const CellClasses& classes_;
  std::vector<std::uint8_t> tolerated_;
  const std::vector<double>& yaws_;
  double along_, across_;            // half box [cells]
  double half_length_, half_width_;  // half box [m]
  int window_;                       // cells looked at on every side
  // Only for the clearances that gate the two tests (see fit()).
  detail::Footprints footprints_;
  detail::FootprintTester gates_;
  std::vector<std::uint8_t> edge_may_cross_;
  double inner_radius_;  // the box's inscribed radius [cells]
};

// Labels, reach layer and visited poses' fits of one placement of the box.
struct Placement {
  std::vector<std::uint8_t> labels, reasons, reach, pose_fit;
};

Placement placePlainly(const TraversabilityMap& produced, const CellClasses& classes,
                       const RobotParams& robot) {
  const MapGrid& grid = produced.grid;
  const std::size_t orientations = produced.yaws.size();
  const PlainPoseTests tests(grid, classes, robot, produced.yaws);
  Placement placed;
  placed.labels.assign(grid.cells(), std::uint8_t(CellLabel::kUnknown));
  placed.reasons.assign(grid.cells(), std::uint8_t(CellReason::kNone));
  std::vector<std::uint8_t> fits(grid.cells() * orientations, 0);  // PoseFit, 0 = not yet known
  auto fitOf = [&](int column, int row, int k) {
    std::uint8_t& known = fits[grid.index(column, row) * orientations + std::size_t(k)];
    if (!known) known = std::uint8_t(tests.fit(column, row, k));
    return PoseFit(known);
  };
  for (int row = 0; row < grid.height; ++row)
    for (int column = 0; column < grid.width; ++column) {
      const std::size_t cell = grid.index(column, row);
      const CellState state = classes.state[cell];
      if (state == CellState::kUnknown) continue;
      if (state == CellState::kBlocked) {
        placed.labels[cell] = std::uint8_t(CellLabel::kImpassable);
        placed.reasons[cell] = std::uint8_t(classes.reason[cell]);
        continue;
      }
      PoseFit best = PoseFit::kBlocked;
      for (int k = 0; k < int(orientations) && best != PoseFit::kClear; ++k)
        best = std::max(best, fitOf(column, row, k));
      if (best == PoseFit::kBlocked) {
        placed.labels[cell] = std::uint8_t(CellLabel::kImpassable);
        placed.reasons[cell] = std::uint8_t(CellReason::kTooNarrow);
      } else if (state == CellState::kLowObstacle) {
        placed.labels[cell] = std::uint8_t(CellLabel::kObstacle);
      } else {
        placed.labels[cell] =
            std::uint8_t(best == PoseFit::kClear ? CellLabel::kTraversable : CellLabel::kCareful);
      }
    }

  // Breadth first from the robot's pose: the moves along each heading (forward and back, the
  // box fitting at every cell crossed; their definition is motionPrimitives'), and a turn to the
  // next tried orientation on either side (sorted by angle modulo 180 deg). Every orientation's
  // fit is kept for each cell looked at.
  placed.reach.assign(grid.cells(), 0);
  placed.pose_fit.assign(grid.cells() * orientations, std::uint8_t(PoseFit::kUntested));
  const Eigen::Vector2i start = grid.cellOf(produced.robot_pose.x, produced.robot_pose.y);
  if (produced.robot_orientation < 0 || !grid.inside(start.x(), start.y())) return placed;
  std::vector<int> by_angle(orientations);
  std::iota(by_angle.begin(), by_angle.end(), 0);
  auto wrapped = [&](int k) {
    const double yaw = std::fmod(produced.yaws[std::size_t(k)], std::numbers::pi);
    return yaw < 0 ? yaw + std::numbers::pi : yaw;
  };
  std::sort(by_angle.begin(), by_angle.end(),
            [&](int a, int b) { return wrapped(a) < wrapped(b); });
  auto turnsFrom = [&](int k) {
    std::vector<int> turns;
    const std::size_t n = by_angle.size();
    const std::size_t at =
        std::size_t(std::find(by_angle.begin(), by_angle.end(), k) - by_angle.begin());
    if (n >= 2) turns.push_back(by_angle[(at + 1) % n]);
    if (n > 2) turns.push_back(by_angle[(at + n - 1) % n]);
    return turns;
  };
  const detail::MotionPrimitives moves = detail::motionPrimitives(produced.yaws);
  // The robot's own pose is valid even where the cell-centred tests, half a cell off its exact
  // position, touch something just outside its box.
  const std::size_t own_state =
      grid.index(start.x(), start.y()) * orientations + std::size_t(produced.robot_orientation);
  // Looks at a cell (every orientation's fit kept) and says whether the box fits in k there.
  auto fitsAt = [&](int column, int row, int k) {
    const std::size_t cell = grid.index(column, row);
    for (int other = 0; other < int(orientations); ++other) {
      const std::size_t state = cell * orientations + std::size_t(other);
      PoseFit fit = fitsLabel(placed.labels[cell]) ? fitOf(column, row, other) : PoseFit::kBlocked;
      if (state == own_state && fit == PoseFit::kBlocked) fit = PoseFit::kCareful;
      placed.pose_fit[state] = std::uint8_t(fit);
    }
    return placed.pose_fit[cell * orientations + std::size_t(k)] != std::uint8_t(PoseFit::kBlocked);
  };
  struct Pose {
    int column, row, k;
  };
  std::vector<std::uint8_t> queued(grid.cells() * orientations, 0);
  std::deque<Pose> queue;
  auto stand = [&](int column, int row, int k) {
    std::uint8_t& was = queued[grid.index(column, row) * orientations + std::size_t(k)];
    if (!was) queue.push_back({column, row, k});
    was = 1;
  };
  // The robot stands at its own pose; with its heading a guess, in any orientation that fits.
  for (int k = 0; k < int(orientations); ++k)
    if (fitsAt(start.x(), start.y(), k) &&
        (k == produced.robot_orientation || !produced.robot_heading_known))
      stand(start.x(), start.y(), k);
  while (!queue.empty()) {
    const Pose pose = queue.front();
    queue.pop_front();
    placed.reach[grid.index(pose.column, pose.row)] = 1;
    for (const int index : moves.of_orientation[std::size_t(pose.k)]) {
      const detail::MotionPrimitive& move = moves.moves[std::size_t(index)];
      bool all_fit = true;
      for (const detail::MotionPrimitive::Crossed& crossed : move.crossed) {
        const int c = pose.column + crossed.dx, r = pose.row + crossed.dy;
        if (!grid.inside(c, r) || !fitsAt(c, r, pose.k)) {
          all_fit = false;
          break;
        }
        placed.reach[grid.index(c, r)] = 1;
      }
      if (all_fit) stand(pose.column + move.dx, pose.row + move.dy, pose.k);
    }
    for (int k : turnsFrom(pose.k))
      if (fitsAt(pose.column, pose.row, k)) stand(pose.column, pose.row, k);
  }
  return placed;
}

struct Case {
  const char* scene;
  double robot_width;
  // Uniform orientations tried; over 64 (with the walls' own) the search goes a pose at a time
  // instead of a word of orientations per cell.
  int orientations = 12;
  // The box fits in places the robot cannot get to (the search then completes the fits of the
  // cells it may enter only: the others keep the label loop's first fit).
  bool fits_where_unreached = true;
};

class TraversabilityAgainstReference : public ::testing::TestWithParam<Case> {};

TEST_P(TraversabilityAgainstReference, LabelsReachAndVisitedPosesAreThoseOfThePlainTests) {
  SegmentationParams params;
  params.robot.width = GetParam().robot_width;
  params.map.orientations = GetParam().orientations;
  const auto run = test::simulateAndSegment(GetParam().scene, 150, params);
  ASSERT_TRUE(run.result.trusted()) << run.result.analysis->reason;
  const ScanAnalysis& analysis = *run.result.analysis;
  const TraversabilityMap& produced = run.result.map;
  MapParams grid_params = params.map;
  grid_params.resolution = produced.grid.resolution;
  const CellClasses classes =
      detail::classifyCells(analysis, params.robot, grid_params, &produced.robot_pose);

  // As computeTraversability: with sparse ground, the search runs on the loose placement and a
  // cell that fits only over sparse ground is orange with the reason "too sparse", or "not seen up
  // to the robot's height" where only cells above the scanner's view are within its reach.
  const Placement loose = placePlainly(produced, classes, params.robot);
  Placement merged = loose;
  const bool has_sparse =
      std::any_of(classes.sparse.begin(), classes.sparse.end(), [](std::uint8_t s) { return s; });
  const double outer_radius =
      detail::makeFootprints(params.robot, produced.grid.resolution, produced.yaws, 1).outer_radius;
  const std::vector<std::uint8_t> view_is_why =
      detail::sparseOnlyAboveTheView(classes, produced.grid, int(std::ceil(outer_radius)));
  if (has_sparse) {
    const Placement strict =
        placePlainly(produced, detail::withSparseBlocked(classes), params.robot);
    for (std::size_t cell = 0; cell < produced.grid.cells(); ++cell) {
      merged.labels[cell] = strict.labels[cell];
      merged.reasons[cell] = strict.reasons[cell];
      if (fitsLabel(strict.labels[cell])) continue;
      if (fitsLabel(loose.labels[cell])) {
        merged.labels[cell] = std::uint8_t(CellLabel::kObstacle);
        merged.reasons[cell] =
            std::uint8_t(view_is_why[cell] ? CellReason::kAboveView : CellReason::kSparse);
      } else {
        merged.labels[cell] = loose.labels[cell];
        merged.reasons[cell] = loose.reasons[cell];
      }
    }
  }
  TraversabilityMap reference = produced;  // grid, orientations, robot pose
  reference.labels = merged.labels;
  reference.reasons = merged.reasons;
  // Too narrow only for unobserved cells around: unknown (the production pass; not under test).
  detail::markUnseenSurroundings(classes, outer_radius, reference);
  labelStairs(analysis, params.robot, reference);

  std::size_t label_differences = 0, reach_differences = 0, fit_differences = 0, visited = 0;
  std::string first_label_difference, first_fit_difference;
  for (std::size_t cell = 0; cell < produced.grid.cells(); ++cell) {
    label_differences += produced.labels[cell] != reference.labels[cell] ||
                         produced.reasons[cell] != reference.reasons[cell];
    reach_differences += produced.reach[cell] != loose.reach[cell];
    if (label_differences == 1 && first_label_difference.empty())
      first_label_difference = "first at cell (" + std::to_string(cell % produced.grid.width) +
                               ", " + std::to_string(cell / produced.grid.width) + "): label " +
                               std::to_string(produced.labels[cell]) + ", reference " +
                               std::to_string(reference.labels[cell]);
  }
  const std::size_t orientations = produced.yaws.size();
  ASSERT_EQ(produced.pose_fit.cells() * orientations, loose.pose_fit.size());
  for (std::size_t state = 0; state < loose.pose_fit.size(); ++state) {
    const auto fit = std::uint8_t(produced.pose_fit.at(state / orientations, state % orientations));
    fit_differences += fit != loose.pose_fit[state];
    if (fit_differences == 1 && first_fit_difference.empty())
      first_fit_difference = "first at cell " + std::to_string(state / orientations) +
                             ", orientation " + std::to_string(state % orientations) + ": fit " +
                             std::to_string(fit) + ", reference " +
                             std::to_string(loose.pose_fit[state]);
    visited += loose.pose_fit[state] != std::uint8_t(PoseFit::kUntested);
  }
  EXPECT_EQ(label_differences, 0U) << first_label_difference;
  EXPECT_EQ(reach_differences, 0U);
  EXPECT_EQ(fit_differences, 0U) << first_fit_difference << "; of " << visited
                                 << " poses the reference search visited";
  // The comparison means something: the scene has orange cells, reachable cells and poses the
  // box does not fit in.
  const std::size_t careful = std::size_t(std::count(produced.labels.begin(), produced.labels.end(),
                                                     std::uint8_t(CellLabel::kCareful)));
  EXPECT_GT(careful, 0U);
  EXPECT_GT(produced.reachable_cells, 100U);
  EXPECT_GT(
      std::count(loose.pose_fit.begin(), loose.pose_fit.end(), std::uint8_t(PoseFit::kBlocked)), 0);
  if (GetParam().fits_where_unreached) {
    EXPECT_GT(produced.fits_not_reachable_cells, 100U);
  }
}

INSTANTIATE_TEST_SUITE_P(PeersTableScenes, TraversabilityAgainstReference,
                         ::testing::Values(Case{"garage", 0.85}, Case{"garage", 0.95},
                                           Case{"hallway", 0.85, 12, false},
                                           Case{"doorways", 0.85, 12, false},
                                           Case{"garage", 0.85, 66, false}),
                         [](const ::testing::TestParamInfo<Case>& param_info) {
                           const Case& c = param_info.param;
                           return std::string(c.scene) + "_" +
                                  std::to_string(int(std::lround(c.robot_width * 100))) + "_" +
                                  std::to_string(c.orientations) + "_orientations";
                         });

}  // namespace
}  // namespace clearway
