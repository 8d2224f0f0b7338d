// Moving the robot's box over the map (paper II-D): a cell is traversable when the box centred
// there fits in at least one orientation. The paper's coarse / enlarged / fine steps decide narrow
// passages: fits with half a cell to spare -> green; fits only against the exact point positions
// -> orange ("careful"); otherwise too narrow.

#include "clearway/traversability/traversability_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "../segmentation/parallel.h"
#include "cell_classes.h"
#include "footprints.h"
#include "reachability_search.h"

namespace clearway {
namespace {

using detail::CellClasses;
using detail::CellState;
using detail::Footprints;
using detail::FootprintTester;
using detail::kExactTestSlackCells;
using detail::kGreenMarginCells;
using detail::makeFootprints;

// What the label loop learnt about each pose (cell, orientation), bits for the reachability
// search: it tries the same tests on the same poses, and each costs far more than a look-up.
enum PoseTests : std::uint8_t {
  kEnlargedTried = 1,
  kEnlargedFits = 2,
  kExactTried = 4,
  kExactFits = 8,
};

// Moves the robot's box over every free cell of `classes`: labels, reasons and orientations of
// `map` (whose grid is set).
// With `reach_into`, also searches where the robot can get from its own pose (map.robot_pose),
// with this placement's tests, into that map's reach layer.
void placeRobot(const CellClasses& classes, const RobotParams& robot, const MapParams& params,
                int threads, TraversabilityMap& map, TraversabilityMap* reach_into = nullptr) {
  const Footprints footprints = makeFootprints(robot, params.resolution, map.yaws, threads);
  const int orientations = int(map.yaws.size());
  const FootprintTester tester(map.grid, classes, detail::toleratedUnknownCells(classes, map.grid),
                               footprints, robot);
  // Within the inscribed radius (plus the coarse test's margin) something blocks the enlarged
  // box in every orientation; below inradius - kExactTestSlackCells the exact test cannot pass.
  const double coarse_radius = footprints.inner_radius + kGreenMarginCells;
  const double exact_radius = footprints.inner_radius - kExactTestSlackCells;
  std::vector<std::uint8_t> tried(reach_into ? map.grid.cells() * std::size_t(orientations) : 0, 0);
  auto enlargedFits = [&](int column, int row, std::size_t cell, int k) {
    const bool fits = tester.fitsEnlarged(column, row, k);
    if (!tried.empty())
      tried[cell * std::size_t(orientations) + std::size_t(k)] |=
          std::uint8_t(kEnlargedTried | (fits ? kEnlargedFits : 0));
    return fits;
  };
  auto exactFits = [&](int column, int row, std::size_t cell, int k) {
    const bool fits = tester.fitsExactlyInCell(column, row, k);
    if (!tried.empty())
      tried[cell * std::size_t(orientations) + std::size_t(k)] |=
          std::uint8_t(kExactTried | (fits ? kExactFits : 0));
    return fits;
  };
  detail::parallelChunks(
      std::size_t(map.grid.height), threads, [&](std::size_t begin, std::size_t end, std::size_t) {
        for (int row = int(begin); row < int(end); ++row) {
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
            int fit = -1;
            bool careful = false;
            if (free_radius > footprints.outer_radius) {
              fit = 0;
            } else {
              if (free_radius >= coarse_radius)
                for (int n = 0; n < orientations && fit < 0; ++n) {
                  const int k = (last_fit + n) % orientations;
                  if (enlargedFits(column, row, cell, k)) fit = k;
                }
              if (fit < 0 && tester.lenientClearance(column, row) >= exact_radius)
                for (int n = 0; n < orientations && fit < 0; ++n) {
                  const int k = (last_fit + n) % orientations;
                  if (exactFits(column, row, cell, k)) {
                    fit = k;
                    careful = true;
                  }
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
              map.labels[cell] =
                  std::uint8_t(careful ? CellLabel::kCareful : CellLabel::kTraversable);
            }
          }
        }
      });
  if (!reach_into) return;
  // Where the robot can get from its own pose: the same tests as above, one pose at a time.
  // The label loop above tried every orientation where nothing fits: those cells are settled;
  // what it tried elsewhere is looked up, not tested again.
  detail::searchReachable(
      *reach_into,
      [&](int column, int row, int k) {
        const std::size_t cell = map.grid.index(column, row);
        const auto label = CellLabel(map.labels[cell]);
        if (label != CellLabel::kTraversable && label != CellLabel::kCareful &&
            label != CellLabel::kObstacle)
          return PoseFit::kBlocked;
        const float free_radius = tester.clearance(column, row);
        if (free_radius > footprints.outer_radius) return PoseFit::kClear;
        const std::uint8_t known = tried[cell * std::size_t(orientations) + std::size_t(k)];
        if (free_radius >= coarse_radius &&
            ((known & kEnlargedTried) ? (known & kEnlargedFits) != 0
                                      : tester.fitsEnlarged(column, row, k)))
          return PoseFit::kClear;
        if (tester.lenientClearance(column, row) >= exact_radius &&
            ((known & kExactTried) ? (known & kExactFits) != 0
                                   : tester.fitsExactlyInCell(column, row, k)))
          return PoseFit::kCareful;
        return PoseFit::kBlocked;
      },
      threads);
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
  if (index == detail::kNoOrientation) return std::numeric_limits<double>::quiet_NaN();
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
  map.orientation.assign(cells, detail::kNoOrientation);
  if (!analysis.ground_found || cells == 0) {
    // Nothing can be trusted: one unknown cell under the scanner, and no traversable cell at all.
    map.grid = MapGrid{params.resolution, Eigen::Vector2d::Constant(-params.resolution / 2), 1, 1};
    map.labels.assign(1, std::uint8_t(CellLabel::kUnknown));
    map.reasons.assign(1, std::uint8_t(CellReason::kNone));
    map.orientation.assign(1, detail::kNoOrientation);
    map.counts[0] = 1;
    return map;
  }
  MapParams grid_params = params;
  grid_params.resolution = map.grid.resolution;  // the grid was made with the analysis' resolution

  // The robot stands at its own pose, in its own heading: that orientation is always tried.
  map.yaws = detail::orientationsToTry(analysis, params.orientations);
  map.robot_pose = robotPoseOnMap(analysis, robot, map.yaws);
  map.robot_orientation = detail::orientationIndex(map.yaws, map.robot_pose.yaw);

  const CellClasses classes = detail::classifyCells(analysis, robot, grid_params, &map.robot_pose);
  map.accepted_ground = classes.accepted_ground;
  reportProgress(progress, 0.3);

  // Sparse ground first counts as unobserved: green and careful only where no obstacle taller than
  // the step can hide under the box. Where the box fits only over sparse ground, the cell is orange
  // (probably passable) with the reason "too sparse".
  const bool has_sparse =
      std::any_of(classes.sparse.begin(), classes.sparse.end(), [](std::uint8_t s) { return s; });
  if (!has_sparse) {
    placeRobot(classes, robot, grid_params, threads, map, &map);
  } else {
    TraversabilityMap loose = map;
    // The robot may drive over sparse ground with care: reachability uses the loose placement.
    placeRobot(classes, robot, grid_params, threads, loose, &map);
    placeRobot(detail::withSparseBlocked(classes), robot, grid_params, threads, map);
    auto fits = [](std::uint8_t label) {
      return label == std::uint8_t(CellLabel::kTraversable) ||
             label == std::uint8_t(CellLabel::kCareful) ||
             label == std::uint8_t(CellLabel::kObstacle);
    };
    for (std::size_t cell = 0; cell < cells; ++cell) {
      if (fits(map.labels[cell])) continue;  // fits on vouched-for ground
      if (fits(loose.labels[cell])) {
        map.labels[cell] = std::uint8_t(CellLabel::kObstacle);
        map.reasons[cell] = std::uint8_t(CellReason::kSparse);
      } else {
        // Does not fit even over sparse ground: the reason is not the density.
        map.labels[cell] = loose.labels[cell];
        map.reasons[cell] = loose.reasons[cell];
      }
      map.orientation[cell] = loose.orientation[cell];
    }
  }
  labelStairs(analysis, robot, map);  // never green: climbable with care, or impassable
  for (std::uint8_t label : map.labels)
    ++map.counts[label];
  reportProgress(progress, 0.8);

  for (std::size_t cell = 0; cell < cells; ++cell) {
    const auto label = CellLabel(map.labels[cell]);
    const bool fits = label == CellLabel::kTraversable || label == CellLabel::kCareful ||
                      label == CellLabel::kObstacle;
    if (fits && !map.reach[cell]) ++map.fits_not_reachable_cells;
  }
  reportProgress(progress, 1.0);
  return map;
}

}  // namespace clearway
