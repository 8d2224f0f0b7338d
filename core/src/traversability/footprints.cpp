#include "footprints.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "../segmentation/parallel.h"
#include "distance_field.h"

namespace clearway::detail {
namespace {

// Gaps up to this wide between blocked cells are taken as closed (sparse wall sampling) [m].
constexpr double kWallGapBridge = 0.3;

// OpenCV's 8-bit masks: a set pixel.
constexpr std::uint8_t kMaskSet = 255;
// The clearance is the exact distance to the nearest blocking cell less this [cells]: far above
// the rounding of a float distance of a few thousand cells, far below any radius that matters.
constexpr float kClearanceMarginCells = 1e-3F;

// Rounding allowance of the exact test's cell bounds [m]: far below any distance that matters,
// far above the rounding of a coordinate of a few tens of metres.
constexpr double kBoundsSlack = 1e-9;

// Whether the centre of the cell (dx, dy) lies in a rectangle of half sizes (along, across)
// [cells] turned to (c, s) = (cos, sin) of its yaw.
bool inRectangle(int dx, int dy, double along, double across, double c, double s) {
  return std::abs(dx * c + dy * s) <= along && std::abs(-dx * s + dy * c) <= across;
}

// Integer cell offsets whose centres lie in a rectangle of half sizes (along, across) [cells]
// turned by yaw, outermost last.
std::vector<Offset> rectangleOffsets(double along, double across, double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  const int reach = int(std::ceil(std::hypot(along, across)));
  std::vector<Offset> offsets;
  for (int dy = -reach; dy <= reach; ++dy)
    for (int dx = -reach; dx <= reach; ++dx)
      if (inRectangle(dx, dy, along, across, c, s))
        offsets.push_back({dx, dy, float(dx * dx + dy * dy)});
  // Sorted by squared radius (exact integers), then turned into radii.
  std::sort(offsets.begin(), offsets.end(),
            [](const Offset& a, const Offset& b) { return a.radius < b.radius; });
  for (Offset& o : offsets)
    o.radius = std::sqrt(o.radius);
  return offsets;
}

// The same cells as rectangleOffsets, row by row. Along a row both of the rectangle's tests are
// monotone in dx (rounding included), so its cells in a row are one unbroken span.
std::vector<RowSpan> rectangleRows(double along, double across, double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  const int reach = int(std::ceil(std::hypot(along, across)));
  std::vector<RowSpan> rows;
  for (int dy = -reach; dy <= reach; ++dy) {
    int first = reach + 1, last = -reach - 1;
    for (int dx = -reach; dx <= reach; ++dx)
      if (inRectangle(dx, dy, along, across, c, s)) {
        first = std::min(first, dx);
        last = std::max(last, dx);
      }
    if (first <= last) rows.push_back({dy, first, last});
  }
  return rows;
}

// The offsets of `outer` (from rectangleOffsets) whose cells are in no span of `inner`, still
// sorted.
std::vector<Offset> ringOffsets(const std::vector<Offset>& outer,
                                const std::vector<RowSpan>& inner) {
  std::vector<Offset> ring;
  for (const Offset& o : outer) {
    const bool inside = std::any_of(inner.begin(), inner.end(), [&o](const RowSpan& span) {
      return span.dy == o.dy && o.dx >= span.first && o.dx <= span.last;
    });
    if (!inside) ring.push_back(o);
  }
  return ring;
}

// Offsets are sorted by radius: the index of the first one at or beyond `radius`.
std::size_t beyond(const std::vector<Offset>& offsets, float radius) {
  return std::size_t(std::lower_bound(offsets.begin(), offsets.end(), radius,
                                      [](const Offset& o, float r) { return o.radius < r; }) -
                     offsets.begin());
}

// Two points whose projections on an axis are closer than this are both kept as the extreme [m]:
// far above the rounding of a coordinate of a few tens of metres, far below any distance that
// matters.
constexpr double kTieTolerance = 1e-9;

// The range of a + b over a in [a0, a1], b in [b0, b1] (ends in any order). Rounding is monotone,
// so a + b computed for any a and b in there lies in the computed range.
struct Range {
  double low, high;
  Range(double a0, double a1, double b0, double b1)
      : low(std::min(a0, a1) + std::min(b0, b1)), high(std::max(a0, a1) + std::max(b0, b1)) {}
  double smallestMagnitude() const { return low > 0 ? low : (high < 0 ? -high : 0.0); }
  double largestMagnitude() const { return std::max(-low, high); }
  bool oneSign() const { return low > 0 || high < 0; }
};

// The clearance of every cell (FootprintTester::clearance) from a mask of the cells that do not
// block.
std::vector<float> clearances(const std::vector<std::uint8_t>& free_mask, const MapGrid& grid) {
  std::vector<float> distance = distanceToBlocked(free_mask, grid.width, grid.height);
  for (float& d : distance)
    d -= kClearanceMarginCells;
  return distance;
}

}  // namespace

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

std::vector<double> orientationsToTry(const ScanAnalysis& analysis, int uniform) {
  std::vector<double> yaws;
  for (int k = 0; k < uniform; ++k)
    yaws.push_back(std::numbers::pi * k / uniform);
  const Eigen::Matrix3d rotation = analysis.map_from_scanner.linear();
  for (const Plane& plane : analysis.planes.planes) {
    if (plane.kind != PlaneKind::kWall) continue;
    const Eigen::Vector3d normal = rotation * plane.normal;
    if (normal.head<2>().norm() < kStandingWallNormal) continue;
    const double along_normal = std::atan2(normal.y(), normal.x());
    for (double yaw : {along_normal, along_normal + std::numbers::pi / 2})
      orientationIndex(yaws, yaw);
  }
  return yaws;
}

Footprints makeFootprints(const RobotParams& robot, double resolution,
                          const std::vector<double>& yaws, int threads) {
  Footprints f;
  const double along = robot.length / 2 / resolution, across = robot.width / 2 / resolution;
  f.yaw = yaws;
  f.enlarged.resize(yaws.size());
  f.core.resize(yaws.size());
  f.deep.resize(yaws.size());
  f.rim.resize(yaws.size());
  parallelChunks(yaws.size(), threads, [&](std::size_t begin, std::size_t end, std::size_t) {
    for (std::size_t k = begin; k < end; ++k) {
      f.enlarged[k] = rectangleRows(along + kGreenMarginCells, across + kGreenMarginCells, yaws[k]);
      f.core[k] = rectangleRows(std::max(0.0, along - kCoreInsetCells),
                                std::max(0.0, across - kCoreInsetCells), yaws[k]);
      // The exact test's centres lie within this of the cell's along each axis of the box.
      const double reach =
          2.0 / kExactCentresPerAxis * (std::abs(std::cos(yaws[k])) + std::abs(std::sin(yaws[k])));
      const double inset = reach + kDeepSlackCells;
      f.deep[k] = along > inset && across > inset
                      ? rectangleRows(along - inset, across - inset, yaws[k])
                      : std::vector<RowSpan>{};
      f.rim[k] = ringOffsets(
          rectangleOffsets(along + kRimReachCells, across + kRimReachCells, yaws[k]), f.core[k]);
    }
  });
  f.inner_radius = across;
  f.outer_radius = std::hypot(along + kGreenMarginCells, across + kGreenMarginCells);
  return f;
}

std::vector<std::uint8_t> cellsNearSparse(const std::vector<std::uint8_t>& sparse,
                                          const MapGrid& grid, const Footprints& footprints) {
  // The rim reaches kRimReachCells past the box, the enlarged box kGreenMarginCells (in
  // outer_radius); a sparse cell changes the closing of blocked cells within its half size, and
  // the tolerated-unknown rule looks one cell further. One more cell of margin for rounding.
  const int reach = int(std::ceil(footprints.outer_radius + kRimReachCells)) +
                    int(std::ceil(kWallGapBridge / grid.resolution)) + 2;
  std::vector<std::uint8_t> near(grid.cells(), 0);
  if (grid.cells() == 0) return near;
  // Only read: OpenCV's header wants a non-const pointer.
  const cv::Mat image(grid.height, grid.width, CV_8UC1, const_cast<std::uint8_t*>(sparse.data()));
  cv::Mat grown(grid.height, grid.width, CV_8UC1, near.data());
  cv::dilate(image, grown,
             cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * reach + 1, 2 * reach + 1)),
             cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  return near;
}

std::vector<std::uint8_t> toleratedUnknownCells(const CellClasses& classes, const MapGrid& grid) {
  // Row by row through pointers: a multi-beam frame's map has hundreds of thousands of cells.
  auto maskOf = [&](auto predicate) {
    cv::Mat mask(grid.height, grid.width, CV_8UC1);
    for (int row = 0; row < grid.height; ++row) {
      std::uint8_t* cells = mask.ptr<std::uint8_t>(row);
      const CellState* states = classes.state.data() + grid.index(0, row);
      for (int column = 0; column < grid.width; ++column)
        cells[column] = predicate(states[column]) ? kMaskSet : 0;
    }
    return mask;
  };
  const cv::Mat observed = maskOf([](CellState s) { return s != CellState::kUnknown; });
  const cv::Mat blocked_mask = maskOf([](CellState s) { return s == CellState::kBlocked; });
  const int size = 2 * int(std::ceil(kWallGapBridge / grid.resolution)) + 1;
  cv::Mat enclosed;
  cv::morphologyEx(blocked_mask, enclosed, cv::MORPH_CLOSE,
                   cv::getStructuringElement(cv::MORPH_RECT, cv::Size(size, size)));
  // Beside a blocked cell a gap may hold the obstacle's edge.
  cv::Mat beside_blocked;
  cv::dilate(blocked_mask, beside_blocked,
             cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
  std::vector<std::uint8_t> tolerated(grid.cells(), 0);
  for (int row = 1; row + 1 < grid.height; ++row) {
    const std::uint8_t* above = observed.ptr<std::uint8_t>(row - 1);
    const std::uint8_t* here = observed.ptr<std::uint8_t>(row);
    const std::uint8_t* below = observed.ptr<std::uint8_t>(row + 1);
    const std::uint8_t* closed = enclosed.ptr<std::uint8_t>(row);
    const std::uint8_t* beside = beside_blocked.ptr<std::uint8_t>(row);
    std::uint8_t* out = tolerated.data() + grid.index(0, row);
    for (int column = 1; column + 1 < grid.width; ++column) {
      if (here[column] || closed[column] || beside[column]) continue;
      const int left = column - 1, right = column + 1;
      if ((here[left] && here[right]) || (above[column] && below[column]) ||
          (above[left] && below[right]) || (below[left] && above[right]))
        out[column] = 1;
    }
  }
  return tolerated;
}

namespace {

bool isDrop(const CellClasses& classes, std::size_t cell) {
  return classes.state[cell] == CellState::kBlocked &&
         (classes.reason[cell] == CellReason::kTooSteep ||
          classes.reason[cell] == CellReason::kOtherLevel);
}

// tan(22.5 deg): a direction is nearest the neighbour whose direction lies within this of it.
constexpr double kTanHalfOctant = 0.41421356237309503;

// Free ground the rays passed over, one byte per cell with a ring of zeros around the grid:
// (column + 1, row + 1) holds cell (column, row). The robot's own place is ground whether seen or
// not, and no ray need have passed over it.
class PaddedGroundSeen {
 public:
  PaddedGroundSeen(const CellClasses& classes, const MapGrid& grid)
      : stride_(std::size_t(grid.width) + 2), seen_(stride_ * (std::size_t(grid.height) + 2), 0) {
    const bool own_place = !classes.own_place.empty();
    for (int row = 0; row < grid.height; ++row) {
      // Row by row through pointers: a multi-beam frame's map has hundreds of thousands of cells.
      const CellState* states = classes.state.data() + grid.index(0, row);
      const std::uint8_t* own = own_place ? classes.own_place.data() + grid.index(0, row) : nullptr;
      std::uint8_t* out = seen_.data() + at(0, row);
      for (int column = 0; column < grid.width; ++column)
        out[column] = isFree(states[column]) && !(own && own[column]);
    }
  }
  bool operator()(int column, int row) const { return seen_[at(column, row)] != 0; }
  // Whether any of the cell's eight neighbours is such ground.
  bool besideAny(int column, int row) const {
    const std::uint8_t* here = seen_.data() + at(column, row);
    const std::uint8_t* above = here - stride_;
    const std::uint8_t* below = here + stride_;
    return (above[-1] | above[0] | above[1] | here[-1] | here[1] | below[-1] | below[0] |
            below[1]) != 0;
  }

 private:
  std::size_t at(int column, int row) const {
    return std::size_t(row + 1) * stride_ + std::size_t(column + 1);
  }
  std::size_t stride_;
  std::vector<std::uint8_t> seen_;
};

// Whether the ground ends in the unobserved cell (column, row) along the scanner's rays
// (unknownCellsAnEdgeMayCross).
bool groundEndsIn(const CellClasses& classes, const MapGrid& grid,
                  const PaddedGroundSeen& ground_seen, int column, int row, int reach) {
  if (!ground_seen.besideAny(column, row)) return false;
  const Eigen::Vector2d towards = classes.viewpoint - grid.centre(column, row);
  const double ax = std::abs(towards.x()), ay = std::abs(towards.y());
  const int dc = ax > kTanHalfOctant * ay ? (towards.x() > 0 ? 1 : -1) : 0;
  const int dr = ay > kTanHalfOctant * ax ? (towards.y() > 0 ? 1 : -1) : 0;
  // Outside the grid the padding holds no ground.
  if ((dc == 0 && dr == 0) || !ground_seen(column + dc, row + dr)) return false;
  // A cell at a time along the ray, in cells from the grid's corner.
  const Eigen::Vector2d away = -towards.normalized();
  for (int step = 1; step <= reach; ++step) {
    const auto beyond_column = int(std::floor(column + 0.5 + away.x() * step));
    const auto beyond_row = int(std::floor(row + 0.5 + away.y() * step));
    if (!grid.inside(beyond_column, beyond_row)) return true;
    const std::size_t cell = grid.index(beyond_column, beyond_row);
    if (classes.state[cell] != CellState::kUnknown) return isDrop(classes, cell);
  }
  return true;
}

}  // namespace

std::vector<std::uint8_t> unknownCellsAnEdgeMayCross(const CellClasses& classes,
                                                     const MapGrid& grid, int reach) {
  std::vector<std::uint8_t> crossed(grid.cells(), 0);
  // Beside a drop: the unobserved cells around the drops, which are few.
  for (int row = 0; row < grid.height; ++row) {
    const CellState* states = classes.state.data() + grid.index(0, row);
    for (int column = 0; column < grid.width; ++column) {
      if (states[column] != CellState::kBlocked || !isDrop(classes, grid.index(column, row)))
        continue;
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc)
          if (grid.inside(column + dc, row + dr)) {
            const std::size_t cell = grid.index(column + dc, row + dr);
            if (classes.state[cell] == CellState::kUnknown) crossed[cell] = 1;
          }
    }
  }
  const PaddedGroundSeen ground_seen(classes, grid);
  for (int row = 0; row < grid.height; ++row) {
    const CellState* states = classes.state.data() + grid.index(0, row);
    std::uint8_t* marks = crossed.data() + grid.index(0, row);
    for (int column = 0; column < grid.width; ++column)
      if (states[column] == CellState::kUnknown && !marks[column] &&
          groundEndsIn(classes, grid, ground_seen, column, row, reach))
        marks[column] = 1;
  }
  return crossed;
}

FootprintTester::FootprintTester(const MapGrid& grid, const CellClasses& classes,
                                 const std::vector<std::uint8_t>& tolerated,
                                 const Footprints& footprints, const RobotParams& robot,
                                 int threads)
    : grid_(grid), classes_(classes), footprints_(footprints) {
  half_length_ = robot.length / 2;
  half_width_ = robot.width / 2;
  step_ = grid.resolution / kCentresPerAxis;

  std::vector<std::uint8_t> free_mask(grid.cells()), lenient_mask(grid.cells());
  for (std::size_t cell = 0; cell < grid.cells(); ++cell) {
    free_mask[cell] = isFree(classes.state[cell]);
    lenient_mask[cell] = free_mask[cell] || tolerated[cell];
  }
  // The two distance transforms side by side.
  parallelChunks(2, threads, [&](std::size_t begin, std::size_t end, std::size_t) {
    for (std::size_t which = begin; which < end; ++which)
      (which == 0 ? clearance_ : lenient_clearance_) =
          clearances(which == 0 ? free_mask : lenient_mask, grid);
  });

  for (const auto& offsets : footprints.rim)
    for (const Offset& o : offsets)
      pad_ = std::max({pad_, std::abs(o.dx), std::abs(o.dy)});
  for (const auto& spans : footprints.enlarged)
    for (const RowSpan& span : spans)
      pad_ = std::max({pad_, std::abs(span.dy), std::abs(span.first), std::abs(span.last)});
  stride_ = grid.width + 2 * pad_;
  const std::size_t padded = std::size_t(stride_) * std::size_t(grid.height + 2 * pad_);
  strict_.assign(padded, 1);
  lenient_.assign(padded, kBlockedAtCentre);
  point_cell_.assign(grid.cells(), kNoPoints);
  const std::vector<std::uint8_t> edge_may_cross =
      unknownCellsAnEdgeMayCross(classes, grid, int(std::ceil(footprints.outer_radius)));
  for (int row = 0; row < grid.height; ++row)
    for (int column = 0; column < grid.width; ++column) {
      const std::size_t cell = grid.index(column, row), here = paddedIndex(column, row);
      const CellState state = classes.state[cell];
      strict_[here] = state == CellState::kBlocked || state == CellState::kUnknown;
      if (state == CellState::kBlocked) {
        lenient_[here] = classes.blocked_by_points_only[cell] ? kBlockedByPoints : kBlockedAtCentre;
      } else if (state == CellState::kUnknown) {
        lenient_[here] = tolerated[cell]        ? kPassable
                         : edge_may_cross[cell] ? kBlockedWhole
                                                : kBlockedAtCentre;
      } else {
        lenient_[here] = kPassable;
      }
      const std::uint32_t first = classes.point_start[cell], last = classes.point_start[cell + 1];
      if (first == last) continue;
      point_cell_[cell] = std::uint32_t(point_bounds_.size());
      PointBounds& bounds = point_bounds_.emplace_back();
      bounds.min_x = bounds.max_x = classes.xs[first];
      bounds.min_y = bounds.max_y = classes.ys[first];
      for (std::uint32_t p = first + 1; p < last; ++p) {
        bounds.min_x = std::min(bounds.min_x, double(classes.xs[p]));
        bounds.max_x = std::max(bounds.max_x, double(classes.xs[p]));
        bounds.min_y = std::min(bounds.min_y, double(classes.ys[p]));
        bounds.max_y = std::max(bounds.max_y, double(classes.ys[p]));
      }
    }
  const std::size_t slots = point_bounds_.size() * footprints.yaw.size();
  // Left uninitialised: a slot is read only once its state says it was filled, and a multi-beam
  // frame's map has hundreds of thousands of slots of which few are ever filled.
  extremes_.reset(new Extremes[slots]);
  slot_state_ = std::make_unique<std::atomic<std::uint8_t>[]>(slots);  // all kSlotEmpty
  auto linear = [&](const std::vector<std::vector<Offset>>& lists) {
    std::vector<std::vector<std::ptrdiff_t>> result;
    for (const auto& offsets : lists) {
      result.emplace_back();
      for (const Offset& o : offsets)
        result.back().push_back(std::ptrdiff_t(o.dy) * stride_ + o.dx);
    }
    return result;
  };
  // Running counts per padded row, and the footprints as runs along rows.
  const auto padded_rows = std::size_t(grid.height + 2 * pad_);
  auto runningCounts = [&](const std::vector<std::uint8_t>& codes, std::uint8_t least) {
    std::vector<std::uint16_t> counts(padded_rows * std::size_t(stride_ + 1));
    for (std::size_t row = 0; row < padded_rows; ++row) {
      const std::uint8_t* cells = codes.data() + row * std::size_t(stride_);
      std::uint16_t* running = counts.data() + row * std::size_t(stride_ + 1);
      running[0] = 0;
      for (std::size_t column = 0; column < std::size_t(stride_); ++column)
        running[column + 1] = std::uint16_t(running[column] + (cells[column] >= least));
    }
    return counts;
  };
  strict_counts_ = runningCounts(strict_, 1);
  lenient_counts_ = runningCounts(lenient_, 1);
  centre_counts_ = runningCounts(lenient_, kBlockedAtCentre);
  auto runs = [&](const std::vector<std::vector<RowSpan>>& lists) {
    std::vector<std::vector<Run>> result;
    for (const auto& spans : lists) {
      result.emplace_back();
      for (const RowSpan& span : spans) {
        const std::ptrdiff_t row_start = std::ptrdiff_t(span.dy) * (stride_ + 1);
        result.back().push_back({row_start + span.first, row_start + span.last + 1});
      }
    }
    return result;
  };
  enlarged_runs_ = runs(footprints.enlarged);
  core_runs_ = runs(footprints.core);
  deep_runs_ = runs(footprints.deep);
  rim_ = linear(footprints.rim);

  // The 5 x 5 centres, the cell's centre first, then outwards.
  static constexpr int kOrder[kCentresPerAxis] = {0, -1, 1, -2, 2};
  for (const double yaw : footprints.yaw) {
    Turn turn;
    turn.c = std::cos(yaw);
    turn.s = std::sin(yaw);
    turn.shift = 2 * step_ * (std::abs(turn.c) + std::abs(turn.s));
    std::size_t i = 0;
    for (int sy : kOrder)
      for (int sx : kOrder) {
        turn.du[i] = (sx * turn.c + sy * turn.s) * step_;
        turn.dv[i] = (-sx * turn.s + sy * turn.c) * step_;
        ++i;
      }
    turns_.push_back(turn);
  }
}

const FootprintTester::Extremes* FootprintTester::extremes(std::size_t cell, std::size_t k) const {
  const std::size_t slot = std::size_t(point_cell_[cell]) * footprints_.yaw.size() + k;
  std::atomic<std::uint8_t>& state = slot_state_[slot];
  if (state.load(std::memory_order_acquire) == kSlotReady) return &extremes_[slot];
  std::uint8_t expected = kSlotEmpty;
  if (!state.compare_exchange_strong(expected, kSlotFilling, std::memory_order_acq_rel))
    return state.load(std::memory_order_acquire) == kSlotReady ? &extremes_[slot] : nullptr;
  const double c = turns_[k].c, s = turns_[k].s;
  const std::uint32_t first = classes_.point_start[cell], last = classes_.point_start[cell + 1];
  // One pass: the least and most projection on each axis, and the runners-up to tell ties.
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  std::array<double, 4> best, runner_up;  // -u, +u, -v, +v as values to minimise
  best.fill(kInfinity);
  runner_up.fill(kInfinity);
  Extremes found{};
  for (std::uint32_t p = first; p < last; ++p) {
    const double x = classes_.xs[p], y = classes_.ys[p];
    const double u = x * c + y * s, v = -x * s + y * c;
    const std::array<double, 4> values = {u, -u, v, -v};
    for (std::size_t e = 0; e < 4; ++e) {
      if (values[e] < best[e]) {
        runner_up[e] = best[e];
        best[e] = values[e];
        found[e] = p;
      } else if (values[e] < runner_up[e]) {
        runner_up[e] = values[e];
      }
    }
  }
  for (std::size_t e = 0; e < 4; ++e)
    if (runner_up[e] - best[e] < kTieTolerance) found[e] = kSeveral;
  extremes_[slot] = found;
  state.store(kSlotReady, std::memory_order_release);
  return &extremes_[slot];
}

template <typename Add>
bool FootprintTester::addCellPoints(std::size_t cell, std::size_t k, const Eigen::Vector2d& centre,
                                    Add&& add) const {
  const std::uint32_t first = classes_.point_start[cell], last = classes_.point_start[cell + 1];
  if (first == last) return true;
  const Turn& turn = turns_[k];
  const double c = turn.c, s = turn.s, shift = turn.shift;
  // The cell's points as a whole, by their bounds in the box's frame.
  const PointBounds& b = point_bounds_[point_cell_[cell]];
  const double x0 = b.min_x - centre.x(), x1 = b.max_x - centre.x();
  const double y0 = b.min_y - centre.y(), y1 = b.max_y - centre.y();
  const Range u(x0 * c, x1 * c, y0 * s, y1 * s), v(-x0 * s, -x1 * s, y0 * c, y1 * c);
  // All beyond the box and its centres' reach: none would be gathered.
  if (u.smallestMagnitude() >= half_length_ + shift + kBoundsSlack ||
      v.smallestMagnitude() >= half_width_ + shift + kBoundsSlack)
    return true;
  // All deep inside it: the first one blocks every centre.
  const bool u_inside = u.largestMagnitude() < half_length_ - shift - kBoundsSlack;
  const bool v_inside = v.largestMagnitude() < half_width_ - shift - kBoundsSlack;
  if (u_inside && v_inside) return false;
  // All across one edge only (inside the other pair of edges for every centre, on one side of
  // the box's axis): a point blocks a centre when it is nearer the axis than the edge, so the
  // point nearest the axis blocks every centre any of them blocks. It stands for them all.
  std::uint32_t only = kSeveral;
  if (v_inside && u.oneSign()) {
    if (const Extremes* e = extremes(cell, k)) only = (*e)[u.low > 0 ? kLeastU : kMostU];
  } else if (u_inside && v.oneSign()) {
    if (const Extremes* e = extremes(cell, k)) only = (*e)[v.low > 0 ? kLeastV : kMostV];
  }
  if (only != kSeveral) {
    add(classes_.xs[only], classes_.ys[only]);
  } else {
    for (std::uint32_t p = first; p < last; ++p)
      add(classes_.xs[p], classes_.ys[p]);
  }
  return true;
}

bool FootprintTester::fitsEnlarged(int column, int row, int orientation) const {
  return !holdsBlocking(strict_counts_, enlarged_runs_[std::size_t(orientation)], column, row);
}

bool FootprintTester::fitsExactlyInCell(int column, int row, int orientation) const {
  // Cheap necessary condition first: nothing that blocks deep inside the box.
  const auto k = std::size_t(orientation);
  if (holdsBlocking(lenient_counts_, core_runs_[k], column, row)) return false;
  // As cheap, and as sure: a cell that blocks by its centre, deep inside the box (the walk over
  // the rim below would find it and stop there).
  if (holdsBlocking(centre_counts_, deep_runs_[k], column, row)) return false;
  const float lenient_clearance = lenientClearance(column, row);
  const std::uint8_t* here = lenient_.data() + paddedIndex(column, row);
  // What could touch the box, gathered once in the box's own frame (u along, v across), then
  // tried against the 5 x 5 centres a fifth of a cell apart, the cell's centre first.
  const Turn& turn = turns_[k];
  const double c = turn.c, s = turn.s;
  const Eigen::Vector2d centre = grid_.centre(column, row);
  const double half_length = half_length_, half_width = half_width_;
  // The 5 x 5 centres lie within `shift` of the cell's centre along u and along v. An item
  // closer than that to the box's inside blocks every one of them (the box cannot fit: stop
  // gathering); one farther than that beyond its edge blocks none (leave it out).
  const double shift = turn.shift;
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
  const std::ptrdiff_t* rim_steps = rim_[k].data();
  const std::size_t rim_count = rim.size();
  for (std::size_t i = beyond(rim, lenient_clearance); i < rim_count; ++i) {
    const std::uint8_t code = here[rim_steps[i]];
    if (code == 0) continue;
    const int cc = column + rim[i].dx, rr = row + rim[i].dy;
    if (code == kBlockedByPoints) {  // only cells inside the grid hold points
      if (!addCellPoints(grid_.index(cc, rr), k, centre, add)) return false;
    } else if (code == kBlockedAtCentre) {
      const Eigen::Vector2d other = grid_.centre(cc, rr);
      add(other.x(), other.y());
    } else {  // kBlockedWhole: its corners stand for it
      const Eigen::Vector2d other = grid_.centre(cc, rr);
      const double half = 0.5 * grid_.resolution;
      for (const double dx : {-half, half})
        for (const double dy : {-half, half})
          add(other.x() + dx, other.y() + dy);
    }
    if (blocks_every_centre) return false;
  }
  for (int i = 0; i < kCentres; ++i) {
    const double du = turn.du[std::size_t(i)], dv = turn.dv[std::size_t(i)];
    const bool clear = std::none_of(items.begin(), items.end(), [&](const Eigen::Vector2d& item) {
      return std::abs(item.x() - du) < half_length && std::abs(item.y() - dv) < half_width;
    });
    if (clear) return true;
  }
  return false;
}

}  // namespace clearway::detail
