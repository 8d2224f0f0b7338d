// Moving the robot's box over the map (paper II-D): a cell is traversable when the box centred
// there fits in at least one orientation. The paper's coarse / enlarged / fine steps decide narrow
// passages: fits with half a cell to spare -> green; fits only against the exact point positions
// -> orange ("careful"); otherwise too narrow.

#include "clearway/traversability/traversability_map.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>

#include "../segmentation/parallel.h"
#include "cell_classes.h"
#include "drive_room.h"
#include "footprints.h"
#include "reach_limit.h"
#include "reachability_search.h"
#include "unseen_surroundings.h"
#include "view_band.h"

namespace clearway {
namespace {

using detail::CellClasses;
using detail::CellState;
using detail::Footprints;
using detail::FootprintTester;
using detail::kExactTestSlackCells;
using detail::kGreenMarginCells;
using detail::makeFootprints;
using detail::TestRadii;

// Rows of a placement are dealt out in turn (row r to part r mod parts), so that the walls, where
// the tests cost, are shared evenly; more parts than threads let a thread that is done early
// (after the reachability search, say) take the rest.
constexpr std::size_t kPartsPerThread = 4;

// A pose's fit between the label loop and completeFits: the coarse test failed, the exact test
// was not tried yet. Never left in the fits the search reads.
constexpr std::uint8_t kCoarseFailed = 4;

bool fitsComplete(const std::uint8_t* fits, std::size_t orientations) {
  return std::none_of(fits, fits + orientations, [](std::uint8_t fit) {
    return fit == std::uint8_t(PoseFit::kUntested) || fit == kCoarseFailed;
  });
}

// The loose placement's fits (PoseFit per cell * orientations + k), and the cells whose tests read
// something sparse cells change (cellsNearSparse): elsewhere the strict placement reads them.
struct ReusedFits {
  std::vector<std::uint8_t> near_sparse;
  const std::vector<std::uint8_t>& fits;
};

// Moves the robot's box over the free cells of `classes` in rows part, part + parts, ...: labels,
// reasons and orientations of `map` (whose grid is set). A cell's tests stop at the first fit: the
// coarse test in every orientation, from the one the last cell fitted in, then the exact test.
// With `pose_fits` not empty, every test made is recorded there (PoseFit per cell * orientations
// + k; kUntested or kCoarseFailed where a test was not made), for completeFits.
// With `reused` (the placement with sparse cells blocked), the cells away from sparse cells whose
// fits are complete read them from the other placement's instead of testing again.
void placeRows(const CellClasses& classes, const Footprints& footprints,
               const FootprintTester& tester, std::size_t part, std::size_t parts,
               TraversabilityMap& map, std::vector<std::uint8_t>& pose_fits,
               const ReusedFits* reused = nullptr) {
  const std::size_t orientations = map.yaws.size();
  // The label's orientation from a cell's complete fits, as the loops below would find it: the
  // first that fits green from the last cell's, else the first that fits at all.
  auto pick = [orientations](const std::uint8_t* fits, int last_fit, int& fit, bool& careful) {
    for (const PoseFit wanted : {PoseFit::kClear, PoseFit::kCareful})
      for (std::size_t n = 0; n < orientations && fit < 0; ++n) {
        const std::size_t k = (std::size_t(last_fit) + n) % orientations;
        if (fits[k] == std::uint8_t(wanted)) {
          fit = int(k);
          careful = wanted == PoseFit::kCareful;
        }
      }
  };
  const TestRadii radii(footprints);
  for (int row = int(part); row < map.grid.height; row += int(parts)) {
    // Neighbouring cells tend to fit the same way: start where the last cell fitted.
    int last_fit = 0;
    for (int column = 0; column < map.grid.width; ++column) {
      const std::size_t cell = map.grid.index(column, row);
      const CellState state = classes.state[cell];
      if (state == CellState::kUnknown) continue;
      if (state == CellState::kBlocked) {
        map.labels[cell] = std::uint8_t(CellLabel::kImpassable);
        map.reasons[cell] = std::uint8_t(classes.reason[cell]);
        continue;
      }
      const float free_radius = tester.clearance(column, row);
      const bool coarse = free_radius >= radii.coarse;
      const bool exact = tester.lenientClearance(column, row) >= radii.exact;
      int fit = -1;
      bool careful = false;
      std::uint8_t* fits = pose_fits.empty() ? nullptr : pose_fits.data() + cell * orientations;
      if (free_radius > footprints.outer_radius) {
        fit = 0;
        if (fits) std::fill_n(fits, orientations, std::uint8_t(PoseFit::kClear));
      } else if (reused && !reused->near_sparse[cell] &&
                 fitsComplete(reused->fits.data() + cell * orientations, orientations)) {
        // The loops below would find the same first fits as the loose placement's tests (and
        // none without either test, as the loose placement found none).
        if (coarse || exact)
          pick(reused->fits.data() + cell * orientations, last_fit, fit, careful);
      } else {
        if (fits) std::fill_n(fits, orientations, std::uint8_t(PoseFit::kUntested));
        if (coarse) {
          for (std::size_t n = 0; n < orientations && fit < 0; ++n) {
            const int k = int((std::size_t(last_fit) + n) % orientations);
            const bool fits_here = tester.fitsEnlarged(column, row, k);
            if (fits) fits[k] = fits_here ? std::uint8_t(PoseFit::kClear) : kCoarseFailed;
            if (fits_here) fit = k;
          }
        } else if (fits) {
          std::fill_n(fits, orientations, kCoarseFailed);
        }
        if (fit < 0 && exact) {
          for (std::size_t n = 0; n < orientations && fit < 0; ++n) {
            const int k = int((std::size_t(last_fit) + n) % orientations);
            const bool fits_here = tester.fitsExactlyInCell(column, row, k);
            if (fits) fits[k] = std::uint8_t(fits_here ? PoseFit::kCareful : PoseFit::kBlocked);
            if (fits_here) {
              fit = k;
              careful = true;
            }
          }
        } else if (fit < 0 && fits) {
          std::fill_n(fits, orientations, std::uint8_t(PoseFit::kBlocked));
        }
      }
      if (fit >= 0) last_fit = fit;
      if (fit < 0) {
        map.labels[cell] = std::uint8_t(CellLabel::kImpassable);
        map.reasons[cell] = std::uint8_t(CellReason::kTooNarrow);
        continue;
      }
      map.orientation[cell] = std::uint8_t(fit);
      if (state == CellState::kLowObstacle) {
        map.labels[cell] = std::uint8_t(CellLabel::kObstacle);
      } else {
        map.labels[cell] = std::uint8_t(careful ? CellLabel::kCareful : CellLabel::kTraversable);
      }
    }
  }
}

// Tasks placing all rows of a placement, kPartsPerThread per thread.
std::vector<std::function<void()>> placementTasks(const CellClasses& classes,
                                                  const Footprints& footprints,
                                                  const FootprintTester& tester, int threads,
                                                  TraversabilityMap& map,
                                                  std::vector<std::uint8_t>& pose_fits,
                                                  const ReusedFits* reused = nullptr) {
  const std::size_t parts = kPartsPerThread * std::size_t(std::max(threads, 1));
  std::vector<std::function<void()>> tasks;
  for (std::size_t part = 0; part < parts; ++part)
    tasks.emplace_back([&classes, &footprints, &tester, &map, &pose_fits, reused, part, parts] {
      placeRows(classes, footprints, tester, part, parts, map, pose_fits, reused);
    });
  return tasks;
}

// Makes the fits of `cells` complete: the tests the label loop did not make, in every
// orientation (placeRows recorded the others).
void completeFits(const std::vector<std::uint32_t>& cells, const Footprints& footprints,
                  const FootprintTester& tester, const MapGrid& grid, int threads,
                  std::vector<std::uint8_t>& pose_fits) {
  const std::size_t orientations = footprints.yaw.size();
  const TestRadii radii(footprints);
  // Cells dealt out in turn, as rows are in placementTasks: the costly ones, beside walls, lie
  // together in the list.
  const std::size_t parts = kPartsPerThread * std::size_t(std::max(threads, 1));
  std::vector<std::function<void()>> tasks;
  for (std::size_t part = 0; part < parts; ++part)
    tasks.emplace_back([&, part] {
      for (std::size_t i = part; i < cells.size(); i += parts) {
        const std::size_t cell = cells[i];
        std::uint8_t* fits = pose_fits.data() + cell * orientations;
        if (fitsComplete(fits, orientations)) continue;
        const int row = int(cell / std::size_t(grid.width));
        const int column = int(cell - std::size_t(row) * std::size_t(grid.width));
        const bool exact = tester.lenientClearance(column, row) >= radii.exact;
        for (std::size_t k = 0; k < orientations; ++k) {
          std::uint8_t& fit = fits[k];
          if (fit == std::uint8_t(PoseFit::kUntested))
            fit = std::uint8_t(detail::testPose(tester, radii, column, row, int(k)));
          else if (fit == kCoarseFailed)
            fit = std::uint8_t(exact && tester.fitsExactlyInCell(column, row, int(k))
                                   ? PoseFit::kCareful
                                   : PoseFit::kBlocked);
        }
      }
    });
  detail::parallelTasks(std::move(tasks), threads);
}

}  // namespace

std::string_view reasonName(CellReason reason) {
  switch (reason) {
    case CellReason::kNone:
      return "";
    case CellReason::kWall:
      return "wall";
    case CellReason::kTooLow:
      return "too low";
    case CellReason::kTooSteep:
      return "too steep";
    case CellReason::kTooNarrow:
      return "too narrow";
    case CellReason::kOtherLevel:
      return "unreachable level";
    case CellReason::kStairsTooSteep:
      return "stairs too steep";
    case CellReason::kSparse:
      return "too sparse";
    case CellReason::kUnseenAround:
      return "too little seen around it";
    case CellReason::kAboveView:
      return "not seen up to the robot's height";
  }
  return "";
}

std::string_view labelName(CellLabel label) {
  switch (label) {
    case CellLabel::kUnknown:
      return "unknown";
    case CellLabel::kTraversable:
      return "traversable";
    case CellLabel::kCareful:
      return "careful";
    case CellLabel::kObstacle:
      return "obstacle";
    case CellLabel::kImpassable:
      return "impassable";
    case CellLabel::kStairs:
      return "stairs";
  }
  return "";
}

double TraversabilityMap::yawDegrees(int column, int row) const {
  const std::uint8_t index = orientation[grid.index(column, row)];
  if (index == kNoOrientation) return std::numeric_limits<double>::quiet_NaN();
  return yaws[index] * 180.0 / std::numbers::pi;
}

TraversabilityMap computeTraversability(const ScanAnalysis& analysis, const RobotParams& robot,
                                        const MapParams& params, int threads,
                                        const ProgressCallback& progress) {
  TraversabilityMap map;
  map.grid = analysis.inputs.grid;
  const std::size_t cells = map.grid.cells();
  map.labels.assign(cells, std::uint8_t(CellLabel::kUnknown));
  map.reasons.assign(cells, std::uint8_t(CellReason::kNone));
  map.orientation.assign(cells, kNoOrientation);
  if (!analysis.ground_found || cells == 0) {
    // Nothing can be trusted: one unknown cell under the scanner, and no traversable cell at all.
    map.grid = MapGrid{params.resolution, Eigen::Vector2d::Constant(-params.resolution / 2), 1, 1};
    map.labels.assign(1, std::uint8_t(CellLabel::kUnknown));
    map.reasons.assign(1, std::uint8_t(CellReason::kNone));
    map.orientation.assign(1, kNoOrientation);
    map.counts[0] = 1;
    return map;
  }
  MapParams grid_params = params;
  grid_params.resolution = map.grid.resolution;  // the grid was made with the analysis' resolution

  // The robot stands at its own pose, in its own heading: that orientation is always tried.
  map.yaws = detail::orientationsToTry(analysis, params.orientations);
  map.robot_pose = robotPoseOnMap(analysis, robot, map.yaws);
  map.robot_orientation = detail::orientationIndex(map.yaws, map.robot_pose.yaw);
  map.robot_heading_known = analysis.robot_from_scanner.has_value();

  // The cells' classes and the box's footprints (which need only the orientations) side by side.
  CellClasses classes;
  Footprints footprints;
  detail::parallelChunks(2, threads, [&](std::size_t begin, std::size_t end, std::size_t) {
    for (std::size_t part = begin; part < end; ++part)
      if (part == 0)
        classes = detail::classifyCells(analysis, robot, grid_params, &map.robot_pose, threads);
      else
        footprints = makeFootprints(robot, grid_params.resolution, map.yaws, 1);
  });
  map.accepted_ground = classes.accepted_ground;
  reportProgress(progress, 0.3);

  // Sparse ground first counts as unobserved: green and careful only where no obstacle taller than
  // the step can hide under the box. Where the box fits only over sparse ground, the cell is orange
  // (probably passable) with the reason "too sparse". The robot may drive over sparse ground with
  // care: reachability uses the loose placement, which takes sparse ground as ground.
  const bool has_sparse =
      std::any_of(classes.sparse.begin(), classes.sparse.end(), [](std::uint8_t s) { return s; });
  const CellClasses strict_classes =
      has_sparse ? detail::withSparseBlocked(classes) : CellClasses{};
  // The tests of both placements, built side by side.
  std::optional<FootprintTester> loose_tester, strict_tester;
  detail::parallelChunks(
      has_sparse ? 2 : 1, threads, [&](std::size_t begin, std::size_t end, std::size_t) {
        for (std::size_t part = begin; part < end; ++part) {
          const CellClasses& tested = part == 0 ? classes : strict_classes;
          (part == 0 ? loose_tester : strict_tester)
              .emplace(map.grid, tested, detail::toleratedUnknownCells(tested, map.grid),
                       footprints, robot, threads);
        }
      });
  TraversabilityMap loose = has_sparse ? map : TraversabilityMap{};
  TraversabilityMap& loose_placement = has_sparse ? loose : map;
  std::vector<std::uint8_t> pose_fits(cells * map.yaws.size(), std::uint8_t(PoseFit::kBlocked));
  detail::parallelTasks(
      placementTasks(classes, footprints, *loose_tester, threads, loose_placement, pose_fits),
      threads);
  // The label loop stops at a cell's first fit; the search needs every pose's fit, but only of the
  // cells it may enter (under a car-mounted sensor a few, in a room nearly all).
  const std::vector<std::uint32_t> may_enter =
      detail::cellsTheSearchMayEnter(map, loose_placement.orientation);
  completeFits(may_enter, footprints, *loose_tester, map.grid, threads, pose_fits);
  // Where the robot can get from its own pose, on the fits found above (cells that are not free,
  // or where the box fits in no orientation, kept kBlocked throughout), beside the placement on
  // vouched-for ground: the search is one thread's work, the rows are shared by all.
  std::vector<std::function<void()>> tasks = {
      [&] { detail::searchReachable(map, pose_fits, may_enter); }};
  std::vector<std::uint8_t> no_pose_fits;  // the first fit of each cell is enough here
  // Away from sparse cells the strict placement's tests are the loose one's: it reads them.
  const ReusedFits reused{has_sparse ? detail::cellsNearSparse(classes.sparse, map.grid, footprints)
                                     : std::vector<std::uint8_t>{},
                          pose_fits};
  if (has_sparse)
    for (auto& task : placementTasks(strict_classes, footprints, *strict_tester, threads, map,
                                     no_pose_fits, &reused))
      tasks.push_back(std::move(task));
  detail::parallelTasks(std::move(tasks), threads);
  if (has_sparse) {
    auto fits = [](std::uint8_t label) { return robotFits(CellLabel(label)); };
    const bool above_view = std::any_of(classes.above_view.begin(), classes.above_view.end(),
                                        [](std::uint8_t a) { return a; });
    const std::vector<std::uint8_t> view_is_why =
        above_view ? detail::sparseOnlyAboveTheView(classes, map.grid,
                                                    int(std::ceil(footprints.outer_radius)))
                   : std::vector<std::uint8_t>(cells, 0);
    for (std::size_t cell = 0; cell < cells; ++cell) {
      if (fits(map.labels[cell])) continue;  // fits on vouched-for ground
      if (fits(loose.labels[cell])) {
        map.labels[cell] = std::uint8_t(CellLabel::kObstacle);
        map.reasons[cell] =
            std::uint8_t(view_is_why[cell] ? CellReason::kAboveView : CellReason::kSparse);
      } else {
        // Does not fit even over sparse ground: the reason is not the density.
        map.labels[cell] = loose.labels[cell];
        map.reasons[cell] = loose.reasons[cell];
      }
      map.orientation[cell] = loose.orientation[cell];
    }
  }
  // Beside a door narrower than the robot's width, a robot wider than long fits turned across it;
  // it cannot drive there, nor through.
  detail::markFitsWithoutRoomToDrive(map, classes, footprints, *loose_tester, pose_fits, robot,
                                     threads);
  detail::markUnseenSurroundings(classes, footprints.outer_radius, map);
  labelStairs(analysis, robot, map);  // never green: climbable with care, or impassable
  for (std::uint8_t label : map.labels)
    ++map.counts[label];
  reportProgress(progress, 0.8);

  for (std::size_t cell = 0; cell < cells; ++cell) {
    if (robotFits(CellLabel(map.labels[cell])) && !map.reach[cell]) ++map.fits_not_reachable_cells;
  }
  map.reach_limit = detail::describeReachLimit(map, footprints.outer_radius);
  reportProgress(progress, 1.0);
  return map;
}

}  // namespace clearway
