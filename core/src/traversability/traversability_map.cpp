// Moving the robot's box over the map (paper II-D): a cell is traversable when the box centred
// there fits in at least one orientation. The paper's coarse / enlarged / fine steps decide narrow
// passages: fits with half a cell to spare -> green; fits only against the exact point positions
// -> orange ("careful"); otherwise too narrow.

#include "clearway/traversability/traversability_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "../segmentation/parallel.h"
#include "cell_classes.h"
#include "reachability_search.h"

namespace clearway {
namespace {

using detail::CellClasses;
using detail::CellState;

// Gaps up to this wide between blocked cells are taken as closed (sparse wall sampling) [m].
constexpr double kWallGapBridge = 0.3;

struct Offset {
  int dx, dy;
  float radius;  // cells
};

// Integer cell offsets whose centres lie in a rectangle of half sizes (along, across) [cells]
// turned by yaw, outermost last.
std::vector<Offset> rectangleOffsets(double along, double across, double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  const int reach = int(std::ceil(std::hypot(along, across)));
  std::vector<Offset> offsets;
  for (int dy = -reach; dy <= reach; ++dy)
    for (int dx = -reach; dx <= reach; ++dx)
      if (std::abs(dx * c + dy * s) <= along && std::abs(-dx * s + dy * c) <= across)
        offsets.push_back({dx, dy, float(dx * dx + dy * dy)});
  // Sorted by squared radius (exact integers), then turned into radii.
  std::sort(offsets.begin(), offsets.end(),
            [](const Offset& a, const Offset& b) { return a.radius < b.radius; });
  for (Offset& o : offsets)
    o.radius = std::sqrt(o.radius);
  return offsets;
}

// The offsets of `outer` that are not in `inner` (both from rectangleOffsets), still sorted.
std::vector<Offset> ringOffsets(const std::vector<Offset>& outer,
                                const std::vector<Offset>& inner) {
  int reach = 0;
  for (const Offset& o : outer)
    reach = std::max({reach, std::abs(o.dx), std::abs(o.dy)});
  const int side = 2 * reach + 1;
  std::vector<std::uint8_t> in_inner(std::size_t(side * side), 0);
  for (const Offset& o : inner)
    if (std::abs(o.dx) <= reach && std::abs(o.dy) <= reach)
      in_inner[std::size_t((o.dy + reach) * side + o.dx + reach)] = 1;
  std::vector<Offset> ring;
  for (const Offset& o : outer)
    if (!in_inner[std::size_t((o.dy + reach) * side + o.dx + reach)]) ring.push_back(o);
  return ring;
}

// Offsets are sorted by radius: the first one at or beyond `radius`.
std::vector<Offset>::const_iterator firstBeyond(const std::vector<Offset>& offsets, float radius) {
  return std::lower_bound(offsets.begin(), offsets.end(), radius,
                          [](const Offset& o, float r) { return o.radius < r; });
}

struct Footprints {
  std::vector<std::vector<Offset>> enlarged;  // nominal + half a cell on every side
  // Nominal less 1.2 cells on every side: a blocked cell centre in here blocks the robot wherever
  // its centre is in the cell (0.4 cells) and wherever the cell's points are (0.71 cells).
  std::vector<std::vector<Offset>> core;
  // Every cell that may hold a point inside the box, less the core (the exact check has cleared
  // the core before it looks at these).
  std::vector<std::vector<Offset>> rim;
  std::vector<double> yaw;
  double inner_radius = 0.0;  // cells: inside this the box is blocked in every orientation
  double outer_radius = 0.0;  // cells: beyond this nothing can touch the enlarged box
};

// Orientations closer than this are one [rad].
constexpr double kSameYaw = 1e-2;
// Orientation indices are bytes, 255 meaning "none fits".
constexpr std::size_t kMaxOrientations = 250;

// Index of `yaw` (modulo 180 deg) in `yaws`, appended when new; -1 when the list is full.
int orientationIndex(std::vector<double>& yaws, double yaw) {
  yaw = std::fmod(std::fmod(yaw, std::numbers::pi) + std::numbers::pi, std::numbers::pi);
  for (std::size_t k = 0; k < yaws.size(); ++k) {
    const double difference = std::abs(yaws[k] - yaw);
    if (std::min(difference, std::numbers::pi - difference) < kSameYaw) return int(k);
  }
  if (yaws.size() >= kMaxOrientations) return -1;
  yaws.push_back(yaw);
  return int(yaws.size()) - 1;
}

// Uniform orientations plus, for every wall, its own direction and the one square to it.
std::vector<double> orientationsToTry(const ScanAnalysis& analysis, int uniform) {
  std::vector<double> yaws;
  for (int k = 0; k < uniform; ++k)
    yaws.push_back(std::numbers::pi * k / uniform);
  const Eigen::Matrix3d rotation = analysis.map_from_scanner.linear();
  for (const Plane& plane : analysis.planes.planes) {
    if (plane.kind != PlaneKind::kWall) continue;
    const Eigen::Vector3d normal = rotation * plane.normal;
    if (normal.head<2>().norm() < 0.7) continue;  // not a standing wall
    const double along_normal = std::atan2(normal.y(), normal.x());
    for (double yaw : {along_normal, along_normal + std::numbers::pi / 2})
      orientationIndex(yaws, yaw);
  }
  return yaws;
}

Footprints makeFootprints(const RobotParams& robot, const MapParams& params,
                          const std::vector<double>& yaws, int threads) {
  Footprints f;
  const double along = robot.length / 2 / params.resolution,
               across = robot.width / 2 / params.resolution;
  f.yaw = yaws;
  f.enlarged.resize(yaws.size());
  f.core.resize(yaws.size());
  f.rim.resize(yaws.size());
  detail::parallelChunks(
      yaws.size(), threads, [&](std::size_t begin, std::size_t end, std::size_t) {
        for (std::size_t k = begin; k < end; ++k) {
          f.enlarged[k] = rectangleOffsets(along + 0.5, across + 0.5, yaws[k]);
          f.core[k] =
              rectangleOffsets(std::max(0.0, along - 1.2), std::max(0.0, across - 1.2), yaws[k]);
          // A cell's points lie within half a diagonal (0.71 cells) of its centre, and the exact
          // check moves the robot's centre up to 0.4 cells: every cell within 1.3 cells may matter.
          f.rim[k] = ringOffsets(rectangleOffsets(along + 1.3, across + 1.3, yaws[k]), f.core[k]);
        }
      });
  f.inner_radius = across;
  f.outer_radius = std::hypot(along + 0.5, across + 0.5);
  return f;
}

class FootprintTester {
 public:
  FootprintTester(const MapGrid& grid, const CellClasses& classes, const cv::Mat& clearance,
                  const cv::Mat& lenient_clearance, const cv::Mat& tolerated,
                  const Footprints& footprints, const RobotParams& robot)
      : grid_(grid),
        classes_(classes),
        clearance_(clearance),
        lenient_clearance_(lenient_clearance),
        footprints_(footprints),
        robot_(robot) {
    // One byte per cell, so each offset costs one read: strict (blocked or unobserved) and lenient
    // (0 passable, 1 blocked by measured points only, 2 blocked otherwise). A border as wide as
    // the largest footprint stands for the outside of the map, which blocks: no bounds checks.
    for (const auto* lists : {&footprints.enlarged, &footprints.rim})
      for (const auto& offsets : *lists)
        for (const Offset& o : offsets)
          pad_ = std::max({pad_, std::abs(o.dx), std::abs(o.dy)});
    stride_ = grid.width + 2 * pad_;
    const std::size_t padded = std::size_t(stride_) * std::size_t(grid.height + 2 * pad_);
    strict_.assign(padded, 1);
    lenient_.assign(padded, 2);
    for (int row = 0; row < grid.height; ++row)
      for (int column = 0; column < grid.width; ++column) {
        const std::size_t cell = grid.index(column, row), here = padded_index(column, row);
        const CellState state = classes.state[cell];
        strict_[here] = state == CellState::kBlocked || state == CellState::kUnknown;
        if (state == CellState::kBlocked) {
          lenient_[here] = classes.blocked_by_points_only[cell] ? 1 : 2;
        } else if (state == CellState::kUnknown) {
          lenient_[here] = tolerated.at<std::uint8_t>(row, column) ? 0 : 2;
        } else {
          lenient_[here] = 0;
        }
      }
    auto linear = [&](const std::vector<std::vector<Offset>>& lists) {
      std::vector<std::vector<std::ptrdiff_t>> result;
      for (const auto& offsets : lists) {
        result.emplace_back();
        for (const Offset& o : offsets)
          result.back().push_back(std::ptrdiff_t(o.dy) * stride_ + o.dx);
      }
      return result;
    };
    enlarged_ = linear(footprints.enlarged);
    core_ = linear(footprints.core);
    rim_ = linear(footprints.rim);
  }

  // Coarse test of the enlarged box: no blocked cell centre inside it.
  bool fitsEnlarged(int column, int row, int orientation) const {
    // Offsets nearer than the clearance are free: the distance transform vouches for them.
    const auto k = std::size_t(orientation);
    const std::uint8_t* here = strict_.data() + padded_index(column, row);
    const std::vector<std::ptrdiff_t>& offsets = enlarged_[k];
    for (std::size_t i = beyond(footprints_.enlarged[k], clearance_.at<float>(row, column));
         i < offsets.size(); ++i)
      if (here[offsets[i]]) return false;
    return true;
  }

  // Exact test of the nominal box: no measured point inside it, and no centre of an unobserved,
  // unreachable or stepped cell.
  // The paper's finer discretisation: the robot's centre may be anywhere in the cell, tried at
  // 5 x 5 positions a fifth of a cell apart, centre first.
  bool fitsExactlyInCell(int column, int row, int orientation) const {
    // Cheap necessary condition first: nothing that blocks deep inside the box.
    const auto k = std::size_t(orientation);
    const float lenient_clearance = lenient_clearance_.at<float>(row, column);
    const std::uint8_t* here = lenient_.data() + padded_index(column, row);
    const std::vector<std::ptrdiff_t>& core = core_[k];
    for (std::size_t i = beyond(footprints_.core[k], lenient_clearance); i < core.size(); ++i)
      if (here[core[i]]) return false;
    // What could touch the box, gathered once in the box's own frame (u along, v across), then
    // tried against the 5 x 5 centres a fifth of a cell apart, the cell's centre first.
    const double yaw = footprints_.yaw[std::size_t(orientation)];
    const double c = std::cos(yaw), s = std::sin(yaw);
    const Eigen::Vector2d centre = grid_.centre(column, row);
    const double half_length = robot_.length / 2, half_width = robot_.width / 2;
    const double step = grid_.resolution / 5.0;
    // The 5 x 5 centres lie within `shift` of the cell's centre along u and along v. An item
    // closer than that to the box's inside blocks every one of them (the box cannot fit: stop
    // gathering); one farther than that beyond its edge blocks none (leave it out).
    const double shift = 2 * step * (std::abs(c) + std::abs(s));
    thread_local std::vector<Eigen::Vector2d> items;
    items.clear();
    bool blocks_every_centre = false;
    auto add = [&](double x, double y) {
      const double dx = x - centre.x(), dy = y - centre.y();
      const double u = std::abs(dx * c + dy * s), v = std::abs(-dx * s + dy * c);
      if (u >= half_length + shift || v >= half_width + shift) return;
      if (u < half_length - shift && v < half_width - shift) blocks_every_centre = true;
      items.emplace_back(dx * c + dy * s, -dx * s + dy * c);
    };
    // Offsets nearer than the clearance are passable: the distance transform vouches for them.
    const std::vector<Offset>& rim = footprints_.rim[k];
    for (std::size_t i = beyond(rim, lenient_clearance); i < rim.size(); ++i) {
      const std::uint8_t code = here[rim_[k][i]];
      if (code == 0) continue;
      const int cc = column + rim[i].dx, rr = row + rim[i].dy;
      if (code == 1) {  // only cells inside the grid hold points
        const std::size_t cell = grid_.index(cc, rr);
        for (std::uint32_t p = classes_.point_start[cell]; p < classes_.point_start[cell + 1]; ++p)
          add(classes_.xs[p], classes_.ys[p]);
      } else {
        const Eigen::Vector2d other = grid_.centre(cc, rr);
        add(other.x(), other.y());
      }
      if (blocks_every_centre) return false;
    }
    static constexpr int kOrder[5] = {0, -1, 1, -2, 2};
    for (int sy : kOrder)
      for (int sx : kOrder) {
        const double du = (sx * c + sy * s) * step, dv = (-sx * s + sy * c) * step;
        const bool clear =
            std::none_of(items.begin(), items.end(), [&](const Eigen::Vector2d& item) {
              return std::abs(item.x() - du) < half_length && std::abs(item.y() - dv) < half_width;
            });
        if (clear) return true;
      }
    return false;
  }

 private:
  std::size_t padded_index(int column, int row) const {
    return std::size_t(row + pad_) * std::size_t(stride_) + std::size_t(column + pad_);
  }
  // Index of the first offset at or beyond `radius` (offsets are sorted by radius).
  static std::size_t beyond(const std::vector<Offset>& offsets, float radius) {
    return std::size_t(firstBeyond(offsets, radius) - offsets.begin());
  }

  const MapGrid& grid_;
  const CellClasses& classes_;
  const cv::Mat& clearance_;
  const cv::Mat& lenient_clearance_;
  int pad_ = 0;
  int stride_ = 0;
  std::vector<std::uint8_t> strict_;   // padded
  std::vector<std::uint8_t> lenient_;  // padded
  // Per orientation, the footprints' offsets as steps in the padded arrays.
  std::vector<std::vector<std::ptrdiff_t>> enlarged_, core_, rim_;
  const Footprints& footprints_;
  const RobotParams& robot_;
};

// Moves the robot's box over every free cell of `classes`: labels, reasons and orientations of
// `map` (whose grid is set).
// With `reach_into`, also searches where the robot can get from its own pose (map.robot_pose),
// with this placement's tests, into that map's reach layer.
void placeRobot(const CellClasses& classes, const RobotParams& robot, const MapParams& params,
                int threads, TraversabilityMap& map, TraversabilityMap* reach_into = nullptr) {
  const MapParams& grid_params = params;
  auto maskOf = [&](auto predicate) {
    cv::Mat mask(map.grid.height, map.grid.width, CV_8UC1);
    for (int row = 0; row < map.grid.height; ++row)
      for (int column = 0; column < map.grid.width; ++column)
        mask.at<std::uint8_t>(row, column) =
            predicate(classes.state[map.grid.index(column, row)]) ? 255 : 0;
    return mask;
  };
  auto close = [&](const cv::Mat& mask, double bridge) {
    const int size = 2 * int(std::ceil(bridge / map.grid.resolution)) + 1;
    cv::Mat closed;
    cv::morphologyEx(mask, closed, cv::MORPH_CLOSE,
                     cv::getStructuringElement(cv::MORPH_RECT, cv::Size(size, size)));
    return closed;
  };
  const cv::Mat free_mask =
      maskOf([](CellState s) { return s == CellState::kGround || s == CellState::kLowObstacle; });
  const cv::Mat blocked_mask = maskOf([](CellState s) { return s == CellState::kBlocked; });
  const cv::Mat unknown_mask = maskOf([](CellState s) { return s == CellState::kUnknown; });

  // Unobserved cells the careful check tolerates: single-cell gaps between observed cells (free or
  // blocked) on two opposite sides, e.g. beside a door jamb where the next beam hit the jamb. Not
  // the open edge of the observed space (past an invisible glass wall, over an unseen drop), not
  // a wider unobserved strip (a thin wall seen end-on), and not the inside of an obstacle between
  // its sparse points.
  const cv::Mat observed = free_mask | blocked_mask;
  const cv::Mat enclosed = close(blocked_mask, kWallGapBridge);
  cv::Mat tolerated(map.grid.height, map.grid.width, CV_8UC1, cv::Scalar(0));
  for (int row = 1; row + 1 < map.grid.height; ++row)
    for (int column = 1; column + 1 < map.grid.width; ++column) {
      if (!unknown_mask.at<std::uint8_t>(row, column) || enclosed.at<std::uint8_t>(row, column))
        continue;
      auto seen = [&](int dc, int dr) {
        return observed.at<std::uint8_t>(row + dr, column + dc) != 0;
      };
      if ((seen(-1, 0) && seen(1, 0)) || (seen(0, -1) && seen(0, 1)) ||
          (seen(-1, -1) && seen(1, 1)) || (seen(-1, 1) && seen(1, -1)))
        tolerated.at<std::uint8_t>(row, column) = 255;
    }

  // Clearance: distance (in cells) from each cell centre to the nearest cell that blocks, strictly
  // (unobserved blocks) and leniently (tolerated unobserved cells do not).
  // The 5x5 mask is within a few per cent of the exact distance; one cell less keeps every use of
  // the clearance conservative (it may only make the tests below do more work, never skip a cell).
  cv::Mat clearance, lenient_clearance;
  cv::distanceTransform(free_mask, clearance, cv::DIST_L2, cv::DIST_MASK_5);
  cv::distanceTransform(free_mask | tolerated, lenient_clearance, cv::DIST_L2, cv::DIST_MASK_5);
  clearance -= 1.0F;
  lenient_clearance -= 1.0F;

  const Footprints footprints = makeFootprints(robot, grid_params, map.yaws, threads);
  const int orientations = int(map.yaws.size());
  const FootprintTester tester(map.grid, classes, clearance, lenient_clearance, tolerated,
                               footprints, robot);
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
            const float free_radius = clearance.at<float>(row, column);
            int fit = -1;
            bool careful = false;
            if (free_radius > footprints.outer_radius) {
              fit = 0;
            } else {
              // Within the inscribed radius something blocks the box in every orientation.
              if (free_radius >= footprints.inner_radius + 0.5F)
                for (int n = 0; n < orientations && fit < 0; ++n) {
                  const int k = (last_fit + n) % orientations;
                  if (tester.fitsEnlarged(column, row, k)) fit = k;
                }
              // A blocked cell's points lie up to 0.71 cells beyond its centre and the robot's
              // centre moves up to 0.57 cells in its cell: below inradius - 1.28 (and the
              // clearance's one-cell margin) no position can fit.
              if (fit < 0 &&
                  lenient_clearance.at<float>(row, column) >= footprints.inner_radius - 2.3F)
                for (int n = 0; n < orientations && fit < 0; ++n) {
                  const int k = (last_fit + n) % orientations;
                  if (tester.fitsExactlyInCell(column, row, k)) {
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
  // The label loop above tried every orientation where nothing fits: those cells are settled.
  detail::searchReachable(
      *reach_into,
      [&](int column, int row, int k) {
        const std::size_t cell = map.grid.index(column, row);
        const auto label = CellLabel(map.labels[cell]);
        if (label != CellLabel::kTraversable && label != CellLabel::kCareful &&
            label != CellLabel::kObstacle)
          return PoseFit::kBlocked;
        const float free_radius = clearance.at<float>(row, column);
        if (free_radius > footprints.outer_radius) return PoseFit::kClear;
        if (free_radius >= footprints.inner_radius + 0.5F && tester.fitsEnlarged(column, row, k))
          return PoseFit::kClear;
        if (lenient_clearance.at<float>(row, column) >= footprints.inner_radius - 2.3F &&
            tester.fitsExactlyInCell(column, row, k))
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
  if (index == 255) return std::numeric_limits<double>::quiet_NaN();
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
  map.orientation.assign(cells, 255);
  if (!analysis.ground_found || cells == 0) {
    // Nothing can be trusted: one unknown cell under the scanner, and no traversable cell at all.
    map.grid = MapGrid{params.resolution, Eigen::Vector2d::Constant(-params.resolution / 2), 1, 1};
    map.labels.assign(1, std::uint8_t(CellLabel::kUnknown));
    map.reasons.assign(1, std::uint8_t(CellReason::kNone));
    map.orientation.assign(1, 255);
    map.counts[0] = 1;
    return map;
  }
  MapParams grid_params = params;
  grid_params.resolution = map.grid.resolution;  // the grid was made with the analysis' resolution

  // The robot stands at its own pose, in its own heading: that orientation is always tried.
  map.yaws = orientationsToTry(analysis, params.orientations);
  map.robot_pose = robotPoseOnMap(analysis, robot, map.yaws);
  map.robot_orientation = orientationIndex(map.yaws, map.robot_pose.yaw);

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
