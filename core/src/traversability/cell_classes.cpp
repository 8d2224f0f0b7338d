#include "cell_classes.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <queue>

#include "../segmentation/parallel.h"
#include "view_band.h"

namespace clearway::detail {
namespace {

// Marks a cell from one of several threads walking beams at once (only ever set to 1).
void markFromAnyThread(std::uint8_t& flag) {
  std::atomic_ref<std::uint8_t>(flag).store(1, std::memory_order_relaxed);
}

// An overhang is "too low" when the lowest thing in the way is above this share of the robot.
constexpr double kOverhangShare = 0.5;
// A cell whose lowest blocking point stands this many steps above the ground holds something the
// floor's beams pass under (a shelf, a table top, a pipe): it casts a shadow over ground that was
// seen (hiddenCells), whatever the robot's height.
constexpr double kOffTheGroundSteps = 2.0;

// Headroom the robot keeps under an overhang [m]: a return this little above its height still
// blocks. The ground under the robot and the overhang are each measured to a few centimetres, and
// a cylinder's or a beam's underside is sampled a few centimetres apart; without it, cells beside
// a pipe bridge 6 cm above a 1.5 m robot were shown passable with the robot's box 3-5 cm under
// the pipe (scripts/variant-sweep, the outdoor scene at 300 lines tilted 35 deg).
constexpr double kHeadroom = 0.05;

// The robot's box at a pose: whether a map position lies in it, grown by `margin` on every side.
// Asked once per measured point: the heading's sine and cosine are taken once.
class RobotBox {
 public:
  RobotBox(const RobotPose& pose, const RobotParams& robot)
      : pose_(pose),
        c_(std::cos(pose.yaw)),
        s_(std::sin(pose.yaw)),
        half_length_(robot.length / 2),
        half_width_(robot.width / 2) {}
  bool contains(double x, double y, double margin) const {
    const double dx = x - pose_.x, dy = y - pose_.y;
    return std::abs(dx * c_ + dy * s_) <= half_length_ + margin &&
           std::abs(-dx * s_ + dy * c_) <= half_width_ + margin;
  }
  // Every position it contains (with `margin`) lies within this distance of its centre.
  double reach(double margin) const {
    return std::hypot(half_length_ + margin, half_width_ + margin);
  }
  const RobotPose& pose() const { return pose_; }

 private:
  RobotPose pose_;
  double c_, s_, half_length_, half_width_;
};

// A low return (`low`: above obstacle_min_height, at most the step) within this distance [m] of a
// return above the step (`tall`) and lower than it is that obstacle's face or foot: seen from
// above, the top of a box just taller than the step is sampled a few centimetres behind its edge
// (a surface seen at a grazing angle), while the face's returns below the step mark where it
// begins. Without it the robot's box stood 4-8 cm into a 0.11 m box (tests' ObstacleFace).
constexpr double kFaceReach = 0.1;

// The step check looks across unobserved gaps up to this wide [m]: as wide as the gaps sparse
// wall sampling leaves (kWallGapBridge, footprints.cpp), and wider than the gaps between scan lines
// near the robot. Across a wider gap the far ground says little about where a step would be.
constexpr double kStepGapReach = 0.3;

// Per obstacle, 1 where it is a low return on the face or foot of a tall one (kFaceReach).
std::vector<std::uint8_t> facesOfTallObstacles(const MapInputs& inputs,
                                               const std::vector<std::uint8_t>& tall,
                                               const std::vector<std::uint8_t>& low) {
  const MapGrid& grid = inputs.grid;
  const std::vector<MapObstacle>& obstacles = inputs.obstacles;
  std::vector<std::uint8_t> face(obstacles.size(), 0);
  if (std::none_of(low.begin(), low.end(), [](std::uint8_t l) { return l; })) return face;
  // The tall returns per cell (CSR).
  std::vector<std::uint32_t> start(grid.cells() + 1, 0);
  for (std::size_t i = 0; i < obstacles.size(); ++i)
    start[obstacles[i].cell + 1] += tall[i];
  for (std::size_t cell = 0; cell < grid.cells(); ++cell)
    start[cell + 1] += start[cell];
  std::vector<std::uint32_t> members(start.back());
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < obstacles.size(); ++i)
    if (tall[i]) members[fill[obstacles[i].cell]++] = std::uint32_t(i);
  const int reach = int(std::ceil(kFaceReach / grid.resolution));
  const float reach_squared = float(kFaceReach * kFaceReach);
  for (std::size_t i = 0; i < obstacles.size(); ++i) {
    if (!low[i]) continue;
    const MapObstacle& o = obstacles[i];
    const int row = int(o.cell / std::size_t(grid.width));
    const int column = int(o.cell - std::size_t(row) * std::size_t(grid.width));
    for (int dr = -reach; dr <= reach && !face[i]; ++dr)
      for (int dc = -reach; dc <= reach && !face[i]; ++dc) {
        if (!grid.inside(column + dc, row + dr)) continue;
        const std::size_t cell = grid.index(column + dc, row + dr);
        for (std::uint32_t k = start[cell]; k < start[cell + 1]; ++k) {
          const MapObstacle& t = obstacles[members[k]];
          const float dx = t.x - o.x, dy = t.y - o.y;
          if (dx * dx + dy * dy <= reach_squared && t.height > o.height) {
            face[i] = 1;
            break;
          }
        }
      }
  }
  return face;
}

// Free ground cells whose samples lie farther apart than kSpacingPerStep x the robot's step, in
// patches at least as wide as the step: a narrower patch (one ground point no triangle reached,
// amid dense ground) cannot hide an obstacle that wide. A cell without a spacing of its own takes
// the sparsest of its neighbours'.
std::vector<std::uint8_t> sparseCells(const MapInputs& inputs, const std::vector<CellState>& state,
                                      const RobotParams& robot, const MapParams& params) {
  const MapGrid& grid = inputs.grid;
  const std::size_t cells = grid.cells();
  std::vector<std::uint8_t> sparse(cells, 0);
  if (inputs.ground_spacing.size() != cells) return sparse;
  const float max_spacing = float(kSpacingPerStep * robot.max_step);
  auto spacingOf = [&](int column, int row) {
    const float own = inputs.ground_spacing[grid.index(column, row)];
    if (std::isfinite(own)) return own;
    float around = 0.0F;
    bool any = false;
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc) {
        if (!grid.inside(column + dc, row + dr)) continue;
        const std::size_t next = grid.index(column + dc, row + dr);
        if (inputs.ground_plane[next] < 0 || !std::isfinite(inputs.ground_spacing[next])) continue;
        around = std::max(around, inputs.ground_spacing[next]);
        any = true;
      }
    return any ? around : own;
  };
  std::vector<std::uint8_t> raw(cells, 0);
  for (int row = 0; row < grid.height; ++row)
    for (int column = 0; column < grid.width; ++column) {
      const std::size_t cell = grid.index(column, row);
      raw[cell] = isFree(state[cell]) && inputs.ground_plane[cell] >= 0 &&
                  spacingOf(column, row) > max_spacing;
    }
  // Opening by a square as wide as the step: patches narrower than the step go. Outside the grid
  // counts as not sparse (the constant border), for the erosion and the dilation alike.
  const int reach = std::max(0, int(std::floor(robot.max_step / params.resolution / 2.0)));
  const cv::Mat square =
      cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * reach + 1, 2 * reach + 1));
  // Rows of the grid are rows of the image (cells are stored row by row).
  const cv::Mat raw_image(grid.height, grid.width, CV_8UC1, raw.data());
  cv::Mat eroded, opened;
  cv::erode(raw_image, eroded, square, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::dilate(eroded, opened, square, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  for (int row = 0; row < grid.height; ++row)
    for (int column = 0; column < grid.width; ++column) {
      const std::size_t cell = grid.index(column, row);
      sparse[cell] = raw[cell] && opened.at<std::uint8_t>(row, column);
    }
  return sparse;
}

// Ground cells in the shadow of the given (overhanging) points, where something as tall as the step
// could stand unseen between the step and the robot's height (docs/ALGORITHM.md, "Sparse scans
// never lie"). All beams leave the scanner, so the space behind a return, along its beam, was seen
// by no beam: behind an overhang (a pipe bridge seen from below) the floor is observed by the beams
// that pass under it, but the robot's band above that floor only as far as they rise. Per cell of
// points, the beams of its lowest and highest point are followed on beyond them over the map; a
// ground cell is hidden where the band between the two continues within (step, height) above its
// ground. The walk ends where that band has left (step, height) above the points' own ground,
// or at the grid's edge.
std::vector<std::uint8_t> hiddenCells(const ScanAnalysis& analysis, const RobotParams& robot,
                                      const std::vector<MapObstacle>& blocking, int threads) {
  const MapInputs& inputs = analysis.inputs;
  const MapGrid& grid = inputs.grid;
  std::vector<std::uint8_t> hidden(grid.cells(), 0);
  // Per cell: its lowest and highest blocking point (their beams bound the shadow behind it).
  struct Span {
    const MapObstacle* low = nullptr;
    const MapObstacle* high = nullptr;
  };
  std::vector<Span> spans(grid.cells());
  std::vector<std::uint32_t> used;
  for (const MapObstacle& o : blocking) {
    Span& span = spans[o.cell];
    if (!span.low) used.push_back(o.cell);
    if (!span.low || o.z < span.low->z) span.low = &o;
    if (!span.high || o.z > span.high->z) span.high = &o;
  }
  const Eigen::Vector3d scanner = analysis.map_from_scanner.translation();
  const double step = robot.max_step, top = robot.height;
  // Half a cell per step of the walk: no cell the beam passes over is skipped.
  const double stride = 0.5 * grid.resolution;
  detail::parallelChunks(
      used.size(), threads, [&](std::size_t begin, std::size_t end, std::size_t) {
        for (std::size_t u = begin; u < end; ++u) {
          const std::uint32_t cell = used[u];
          const MapObstacle& low = *spans[cell].low;
          const MapObstacle& high = *spans[cell].high;
          const Eigen::Vector2d from(low.x, low.y);
          Eigen::Vector2d direction = from - scanner.head<2>();
          const double distance = direction.norm();
          if (distance < stride) continue;  // straight above or below the scanner: no beyond
          direction /= distance;
          // Rise of each beam per metre beyond its point, seen from the scanner.
          const double high_distance =
              std::max(stride, (Eigen::Vector2d(high.x, high.y) - scanner.head<2>()).norm());
          const double low_rise = (low.z - scanner.z()) / distance;
          const double high_rise = (high.z - scanner.z()) / high_distance;
          const double own_ground = double(low.z) - double(low.height);
          const double longest = std::hypot(grid.width, grid.height) * grid.resolution;
          for (double t = stride; t <= longest; t += stride) {
            const double z_low = low.z + low_rise * t, z_high = high.z + high_rise * t;
            const double bottom = std::min(z_low, z_high), upper = std::max(z_low, z_high);
            if (bottom - own_ground >= top || upper - own_ground <= step) break;
            const Eigen::Vector2d at = from + t * direction;
            const Eigen::Vector2i c = grid.cellOf(at.x(), at.y());
            if (!grid.inside(c.x(), c.y())) break;
            const std::size_t index = grid.index(c.x(), c.y());
            if (inputs.ground_plane[index] < 0) continue;
            const double ground = inputs.ground_height[index];
            if (upper - ground > step && bottom - ground < top) markFromAnyThread(hidden[index]);
          }
        }
      });
  return hidden;
}

// `blocking` per obstacle: kBlocks, kOwnBody (the robot: there, but no obstacle) or 0.
constexpr std::uint8_t kBlocks = 1, kOwnBody = 2;

// A neighbouring beam that went on past an obstacle's range by more than this saw the space
// beside it free (anything standing there from the ground up would have stopped it) [m]: a cell,
// well above the range noise.
constexpr double kPassedBy = 0.05;

// Ground cells an obstacle may reach into between two lines (SweepNeighbours, docs/ALGORITHM.md,
// "Where an obstacle ends between two lines"): from each blocking point towards where the
// neighbouring line's beam was at its range, up to (not including) that place, when that beam
// either ended there (what lies beyond its return is its shadow: the low face of a pallet whose
// top the other line hit; or the same obstacle, seen again by the next line) or went on past a
// wedge wider than the density check lets an obstacle hide in (`widest`). From a point the robot
// drives over or under (lower than `step`, or above `top`), from the point itself, where the span
// from its height to the neighbouring beam's at its range reaches between the two.
void markSweepWedges(const MapInputs& inputs, const Eigen::Vector3d& scanner, double widest,
                     double step, double top, const std::vector<std::uint8_t>& blocking,
                     const std::vector<CellState>& state, std::vector<std::uint8_t>& sparse,
                     int threads) {
  const SweepNeighbours& neighbours = inputs.sweep_neighbours;
  if (neighbours.of_obstacle.size() != inputs.obstacles.size()) return;
  const MapGrid& grid = inputs.grid;
  // Half a cell per step: no cell the chord crosses is skipped.
  const double stride = 0.5 * grid.resolution;
  detail::parallelChunks(
      inputs.obstacles.size(), threads, [&](std::size_t begin, std::size_t end, std::size_t) {
        for (std::size_t i = begin; i < end; ++i) {
          if (blocking[i] == kOwnBody) continue;
          const bool blocks = blocking[i] == kBlocks;
          const MapObstacle& o = inputs.obstacles[i];
          const Eigen::Vector3d at_obstacle(o.x, o.y, o.z);
          const double range = (at_obstacle - scanner).norm();
          for (const std::uint32_t neighbour : neighbours.of_obstacle[i]) {
            if (neighbour == SweepNeighbours::kNone) continue;
            Eigen::Vector2d pass;
            double pass_z = 0.0, beyond = 0.0;
            if (neighbour & SweepNeighbours::kBeam) {
              const SweepNeighbours::Beam& beam =
                  neighbours.beams[neighbour & ~SweepNeighbours::kBeam];
              pass = {beam.x, beam.y};
              pass_z = beam.z;
              beyond = beam.beyond;
            } else {
              // The robot's own body hides what lies beyond it. A neighbour that blocks too says
              // the obstacle was there on both lines, not what stands between them at its height:
              // a pipe bridge seen by two lines 0.4 m apart crosses the wedge between them, and
              // was taken for two posts a box could stand between (a random sweep's sparse
              // outdoor scan, CellClasses.AnObstacleSeenByTwoLinesIsNotVouchedForBetweenThem).
              if (blocking[neighbour] == kOwnBody) continue;
              const MapObstacle& n = inputs.obstacles[neighbour];
              const Eigen::Vector3d beam = Eigen::Vector3d(n.x, n.y, n.z) - scanner;
              const double length = beam.norm();
              if (!(length > 0.0)) continue;
              const Eigen::Vector3d at_range = scanner + beam * (range / length);
              pass = at_range.head<2>();
              pass_z = at_range.z();
              beyond = length - range;
            }
            const Eigen::Vector2d from(o.x, o.y);
            const double chord = (pass - from).norm();
            if (blocks && beyond > kPassedBy && chord <= widest) continue;
            if (!blocks) {
              // A point the robot passes over or under, whose neighbour across the sweep passed
              // beside it (or hit the same obstacle) at another height: the obstacle may run on
              // between the two, from its own height to the neighbour's, and where that span
              // reaches into the robot's band it may block there. With the turntable's axis tilted
              // the lines lie one above the other: a 0.13 m box seen only along its low side face,
              // 4-8 cm up, its top between that line and the next one 15 cm higher, was driven
              // over (a helper's clutter scene, 100 lines tilted 15 deg).
              if ((neighbour & SweepNeighbours::kBeam) && !(beyond > kPassedBy)) continue;
              const double neighbour_height = o.height + (pass_z - o.z);
              if (!(std::min(double(o.height), neighbour_height) < top &&
                    std::max(double(o.height), neighbour_height) > step))
                continue;
            }
            const int steps = int(std::ceil(chord / stride));
            for (int k = blocks ? 1 : 0; k < steps; ++k) {
              const Eigen::Vector2d at = from + (pass - from) * (double(k) / steps);
              const Eigen::Vector2i c = grid.cellOf(at.x(), at.y());
              if (!grid.inside(c.x(), c.y())) continue;
              const std::size_t cell = grid.index(c.x(), c.y());
              if (isFree(state[cell])) markFromAnyThread(sparse[cell]);
            }
          }
        }
      });
}

// markSteps looks at the grid in tiles this many cells square, and skips the flat ones.
constexpr int kStepTile = 16;
// What rounding may add to a rise compared with the step (metres): far below any step.
constexpr double kFlatTileMargin = 1e-6;

// Ground cells where the ground steps by more than the robot can take become blocked (too steep):
// cells stepped by a seam (MapInputs::seam_step), and the two ends of a step along a row or a
// column. Heights are compared between cells next to each other, over a short run of cells
// (kStepRunLength: the ground triangles spread a step over the few centimetres between the last
// return below it and the first above, and a step's face seen from the front raises the cell it
// falls in, splitting the step in two), and across a short unobserved gap (kStepGapReach: the
// step's edge may lie anywhere in it, or just inside the lower cell, whose returns were then the
// step's face). Beyond the next cell, what either cell's ground plane rises over the distance is no
// step (a ramp's scan lines leave gaps, and its foot joins the floor over a few cells).
void markSteps(const ScanAnalysis& analysis, const RobotParams& robot, CellClasses& classes,
               int threads) {
  const MapInputs& inputs = analysis.inputs;
  const MapGrid& grid = inputs.grid;
  const std::vector<CellState>& state = classes.state;  // marks go to `stepped` until the end
  // 1 where a ground cell is too steep; set from any thread (rows are shared out, and a step
  // down a column marks a cell of another row).
  std::vector<std::uint8_t> stepped(grid.cells(), 0);
  auto mark = [&](std::size_t cell) {
    if (state[cell] == CellState::kGround) markFromAnyThread(stepped[cell]);
  };
  if (!inputs.seam_step.empty())
    for (std::size_t cell = 0; cell < grid.cells(); ++cell)
      if (inputs.seam_step[cell] > robot.max_step) mark(cell);
  // What the ground plane of `cell` rises over (dc, dr) cells.
  auto planeRise = [&](std::size_t cell, int dc, int dr) {
    const Eigen::Vector3d& plane =
        analysis.height_coefficients[std::size_t(inputs.ground_plane[cell])];
    return (plane[1] * dc + plane[2] * dr) * grid.resolution;
  };
  // Whether the ground steps between ground cell `from` and `to`, (dc, dr) cells on.
  auto isStep = [&](std::size_t from, std::size_t to, int dc, int dr) {
    const double rise = inputs.ground_height[to] - inputs.ground_height[from];
    if (std::abs(dc) + std::abs(dr) == 1) return std::abs(rise) > robot.max_step;
    const double from_rise = planeRise(from, dc, dr);
    if (std::abs(rise - from_rise) <= robot.max_step) return false;
    return inputs.ground_plane[to] == inputs.ground_plane[from] ||
           std::abs(rise - planeRise(to, dc, dr)) > robot.max_step;
  };
  const int gap_cells = int(std::floor(kStepGapReach / grid.resolution));
  const int run_cells = std::max(1, int(std::floor(kStepRunLength / grid.resolution + 1e-9)));
  const int look_back = std::max(gap_cells + 1, run_cells);
  // A ground cell against the ground cells before it along one axis (`stride` apart in the grid's
  // index, `available` of them inside the grid, (dc, dr) the axis), nearest first: the next ground
  // cell across unobserved cells, then over the run those with ground cells between, as long as
  // no two of these differ by a step themselves (a sharp step stands for itself).
  auto compareBack = [&](std::size_t cell, std::size_t stride, int available, int dc, int dr) {
    std::size_t nearer = cell;  // the last ground cell met before the one looked at
    int nearer_distance = 0;
    for (int d = 1; d <= std::min(look_back, available); ++d) {
      const std::size_t earlier = cell - std::size_t(d) * stride;
      if (inputs.ground_plane[earlier] < 0) {
        if (state[earlier] != CellState::kUnknown) return;  // blocked by points: they stand for it
        continue;
      }
      if (nearer_distance > 0 &&
          (d > run_cells ||
           isStep(earlier, nearer, (d - nearer_distance) * dc, (d - nearer_distance) * dr)))
        return;
      if (isStep(earlier, cell, d * dc, d * dr)) {
        mark(earlier);
        mark(cell);
        return;
      }
      nearer = earlier;
      nearer_distance = d;
    }
  };
  // A tile whose ground cells, with those the look-back reaches before it along rows and columns,
  // lie within the step less what their planes may rise over the look-back holds no two that
  // differ by a step: none of its cells is compared (most of a road or a floor; isStep could only
  // say no).
  auto flatTile = [&](int first_row, int end_row, int first_column, int end_column) {
    float lowest = std::numeric_limits<float>::max(), highest = -lowest;
    double steepest = 0.0;  // the largest height coefficient along x or y of the planes there
    for (int row = std::max(0, first_row - look_back); row < end_row; ++row)
      for (int column = std::max(0, first_column - look_back); column < end_column; ++column) {
        const std::size_t cell = grid.index(column, row);
        const int plane = inputs.ground_plane[cell];
        if (plane < 0) continue;
        lowest = std::min(lowest, inputs.ground_height[cell]);
        highest = std::max(highest, inputs.ground_height[cell]);
        const Eigen::Vector3d& c = analysis.height_coefficients[std::size_t(plane)];
        steepest = std::max({steepest, std::abs(c[1]), std::abs(c[2])});
      }
    if (lowest > highest) return true;  // no ground at all
    return double(highest) - double(lowest) + steepest * look_back * grid.resolution <=
           robot.max_step - kFlatTileMargin;
  };
  const int tile_rows = (grid.height + kStepTile - 1) / kStepTile;
  detail::parallelChunks(
      std::size_t(tile_rows), threads,
      [&](std::size_t tile_begin, std::size_t tile_end, std::size_t) {
        for (int tile_row = int(tile_begin); tile_row < int(tile_end); ++tile_row) {
          const int first_row = tile_row * kStepTile;
          const int end_row = std::min(first_row + kStepTile, grid.height);
          for (int first_column = 0; first_column < grid.width; first_column += kStepTile) {
            const int end_column = std::min(first_column + kStepTile, grid.width);
            if (flatTile(first_row, end_row, first_column, end_column)) continue;
            for (int row = first_row; row < end_row; ++row)
              for (int column = first_column; column < end_column; ++column) {
                const std::size_t cell = grid.index(column, row);
                if (inputs.ground_plane[cell] < 0) continue;
                compareBack(cell, 1, column, 1, 0);
                compareBack(cell, std::size_t(grid.width), row, 0, 1);
              }
          }
        }
      });
  for (std::size_t cell = 0; cell < grid.cells(); ++cell)
    if (stepped[cell]) {
      classes.state[cell] = CellState::kBlocked;
      classes.reason[cell] = CellReason::kTooSteep;
    }
}

// Where beams went down through the ground's level over unobserved ground the floor ends: those
// cells are drops (floor_crossings.h). Their blocking positions (with their cells) are where the
// beams crossed and each cell's centre (an unobserved cell blocks the exact test by its centre), so
// that a box's edge keeps off a drop's near side too. None inside `recorded_box`, the robot's
// recorded place: a beam lost there met its own dark body.
struct Drops {
  std::vector<Eigen::Vector2f> positions;
  std::vector<std::uint32_t> cells;
};
Drops dropsWhereBeamsCrossedTheFloor(const MapInputs& inputs, const RobotBox* recorded_box) {
  Drops drops;
  const MapGrid& grid = inputs.grid;
  std::vector<std::uint8_t> is_drop(inputs.floor_crossings.empty() ? 0 : grid.cells(), 0);
  for (const FloorCrossing& crossing : inputs.floor_crossings) {
    if (recorded_box && recorded_box->contains(crossing.x, crossing.y, 0.0)) continue;
    if (!is_drop[crossing.cell]) {
      is_drop[crossing.cell] = 1;
      const Eigen::Vector2d centre = grid.centre(int(crossing.cell % std::uint32_t(grid.width)),
                                                 int(crossing.cell / std::uint32_t(grid.width)));
      drops.positions.emplace_back(float(centre.x()), float(centre.y()));
      drops.cells.push_back(crossing.cell);
    }
    drops.positions.emplace_back(crossing.x, crossing.y);
    drops.cells.push_back(crossing.cell);
  }
  return drops;
}

}  // namespace

std::vector<int> reachableGround(const ScanAnalysis& analysis, double max_step) {
  std::vector<int> accepted = {analysis.reference_ground};
  std::queue<int> frontier;
  frontier.push(analysis.reference_ground);
  while (!frontier.empty()) {
    const int plane = frontier.front();
    frontier.pop();
    for (const GroundContact& contact : analysis.inputs.contacts) {
      if (contact.step > max_step) continue;
      const int other = contact.a == plane ? contact.b : (contact.b == plane ? contact.a : -1);
      if (other < 0 || std::find(accepted.begin(), accepted.end(), other) != accepted.end())
        continue;
      accepted.push_back(other);
      frontier.push(other);
    }
  }
  return accepted;
}

CellClasses classifyCells(const ScanAnalysis& analysis, const RobotParams& robot,
                          const MapParams& params, const RobotPose* own_place, int threads) {
  const MapInputs& inputs = analysis.inputs;
  const MapGrid& grid = inputs.grid;
  const std::size_t cells = grid.cells();
  CellClasses classes;
  classes.state.assign(cells, CellState::kUnknown);
  classes.reason.assign(cells, CellReason::kNone);
  classes.blocked_by_points_only.assign(cells, 0);
  classes.accepted_ground = reachableGround(analysis, robot.max_step);
  classes.viewpoint = analysis.map_from_scanner.translation().head<2>();
  std::vector<bool> accepted(analysis.planes.planes.size(), false);
  for (int g : classes.accepted_ground)
    accepted[std::size_t(g)] = true;

  for (std::size_t cell = 0; cell < cells; ++cell) {
    const int plane = inputs.ground_plane[cell];
    if (plane < 0) continue;
    if (accepted[std::size_t(plane)]) {
      classes.state[cell] = CellState::kGround;
    } else {
      classes.state[cell] = CellState::kBlocked;
      classes.reason[cell] = CellReason::kOtherLevel;
    }
  }

  // Points: low ones are passable obstacles; those between the step and the robot's height
  // block; a drop deeper than a step blocks too. Overhead points do not matter.
  std::vector<float> lowest_block(cells, std::numeric_limits<float>::max());
  std::vector<std::uint32_t> blocking_count(cells, 0);
  const float min_height = float(params.obstacle_min_height);
  const float step = float(robot.max_step), top = float(robot.height + kHeadroom);
  const RobotBox own_box(own_place ? *own_place : RobotPose{}, robot);  // used with own_place
  // Returns from the robot's own body, found once per point.
  std::vector<std::uint8_t> own_body(inputs.obstacles.size(), 0);
  if (own_place)
    for (std::size_t i = 0; i < inputs.obstacles.size(); ++i)
      own_body[i] = own_box.contains(inputs.obstacles[i].x, inputs.obstacles[i].y, 0.0);
  std::vector<std::uint8_t> is_tall(inputs.obstacles.size(), 0), is_low(inputs.obstacles.size(), 0);
  for (std::size_t i = 0; i < inputs.obstacles.size(); ++i) {
    const MapObstacle& o = inputs.obstacles[i];
    is_tall[i] = o.height > step && o.height < top && !own_body[i];
    is_low[i] = o.height > min_height && o.height <= step && !own_body[i];
  }
  const std::vector<std::uint8_t> face = facesOfTallObstacles(inputs, is_tall, is_low);
  std::vector<std::uint8_t> blocking_point(inputs.obstacles.size(), 0);
  for (std::size_t i = 0; i < inputs.obstacles.size(); ++i)
    blocking_point[i] =
        is_tall[i] || face[i] || (inputs.obstacles[i].height < -step && !own_body[i]);
  auto blocks = [&](std::size_t i) { return blocking_point[i] != 0; };
  for (std::size_t i = 0; i < inputs.obstacles.size(); ++i) {
    const MapObstacle& o = inputs.obstacles[i];
    if (own_body[i]) continue;
    if (blocks(i)) {
      lowest_block[o.cell] = std::min(lowest_block[o.cell], std::abs(o.height));
      ++blocking_count[o.cell];
      if (o.height < -step) classes.reason[o.cell] = CellReason::kTooSteep;
    } else if (o.height > min_height && o.height <= step &&
               classes.state[o.cell] != CellState::kBlocked) {
      classes.state[o.cell] = CellState::kLowObstacle;
    }
  }
  const Drops drops = dropsWhereBeamsCrossedTheFloor(
      inputs, own_place && analysis.robot_from_scanner ? &own_box : nullptr);
  for (const std::uint32_t cell : drops.cells) {
    ++blocking_count[cell];
    classes.reason[cell] = CellReason::kTooSteep;
  }
  for (std::size_t cell = 0; cell < cells; ++cell) {
    if (blocking_count[cell] == 0) continue;
    const bool was_blocked = classes.state[cell] == CellState::kBlocked;
    classes.state[cell] = CellState::kBlocked;
    if (classes.reason[cell] != CellReason::kTooSteep)
      classes.reason[cell] = lowest_block[cell] > kOverhangShare * robot.height
                                 ? CellReason::kTooLow
                                 : CellReason::kWall;
    classes.blocked_by_points_only[cell] = was_blocked ? 0 : 1;
  }

  markSteps(analysis, robot, classes, threads);

  // The robot stands on its own place: the floor under it is ground, seen or not.
  std::vector<std::uint8_t>& own_cells = classes.own_place;
  if (own_place) {
    own_cells.assign(cells, 0);
    const double margin = 0.5 * grid.resolution;
    // Only the cells around the box can lie in it.
    const double reach = own_box.reach(margin);
    const Eigen::Vector2i low = grid.cellOf(own_box.pose().x - reach, own_box.pose().y - reach);
    const Eigen::Vector2i high = grid.cellOf(own_box.pose().x + reach, own_box.pose().y + reach);
    for (int row = std::max(low.y(), 0); row <= std::min(high.y(), grid.height - 1); ++row)
      for (int column = std::max(low.x(), 0); column <= std::min(high.x(), grid.width - 1);
           ++column) {
        const std::size_t cell = grid.index(column, row);
        const Eigen::Vector2d centre = grid.centre(column, row);
        if (blocking_count[cell] != 0 || !own_box.contains(centre.x(), centre.y(), margin))
          continue;
        // The half cell around the box is not another level's ground: a box placed against a
        // pallet's top would take in a strip of it.
        if (classes.reason[cell] == CellReason::kOtherLevel &&
            !own_box.contains(centre.x(), centre.y(), 0.0))
          continue;
        classes.state[cell] = CellState::kGround;
        classes.reason[cell] = CellReason::kNone;
        own_cells[cell] = 1;
      }
  }
  // Free ground whose samples are too far apart to vouch for it, or that lies in the shadow of a
  // blocking point.
  classes.sparse = sparseCells(inputs, classes.state, robot, params);
  // Only what stands off the ground casts such shadows (cells whose lowest blocking point is
  // kOffTheGroundSteps above it: a shelf, a table top, a pipe): behind a thing standing on the
  // ground no ground is seen while its beams' continuations are in the band, and the cells along
  // the edge of its shadow (a door jamb's, seen through the door) would only be caught by the
  // walk's discretisation. Counting only what is too low to pass under (kOverhangShare) left a
  // shelf 0.6 m up, its end 0.2 m beyond its last samples, for the robot's box to stand under.
  std::vector<MapObstacle> overhanging;
  for (std::size_t i = 0; i < inputs.obstacles.size(); ++i)
    if (const CellReason reason = classes.reason[inputs.obstacles[i].cell];
        blocks(i) && (reason == CellReason::kTooLow ||
                      (reason != CellReason::kTooSteep && lowest_block[inputs.obstacles[i].cell] >
                                                              kOffTheGroundSteps * robot.max_step)))
      overhanging.push_back(inputs.obstacles[i]);
  const std::vector<std::uint8_t> hidden = hiddenCells(analysis, robot, overhanging, threads);
  for (std::size_t cell = 0; cell < cells; ++cell)
    if (hidden[cell] && isFree(classes.state[cell])) classes.sparse[cell] = 1;
  // Ground whose band up to the robot's height (and the headroom it keeps) no beam rose through.
  classes.above_view = cellsAboveTheView(analysis, classes.state, own_cells, top);
  for (std::size_t cell = 0; cell < cells; ++cell)
    if (classes.above_view[cell]) classes.sparse[cell] = 1;
  std::vector<std::uint8_t> blocking(inputs.obstacles.size(), 0);
  for (std::size_t i = 0; i < inputs.obstacles.size(); ++i)
    blocking[i] = own_body[i] ? kOwnBody : (blocks(i) ? kBlocks : 0);
  markSweepWedges(inputs, analysis.map_from_scanner.translation(), kSpacingPerStep * robot.max_step,
                  step, top, blocking, classes.state, classes.sparse, threads);

  // Blocking points in CSR layout for the exact narrow-passage check.
  classes.point_start.assign(cells + 1, 0);
  for (std::size_t cell = 0; cell < cells; ++cell)
    classes.point_start[cell + 1] = classes.point_start[cell] + blocking_count[cell];
  classes.xs.resize(classes.point_start[cells]);
  classes.ys.resize(classes.point_start[cells]);
  std::vector<std::uint32_t> fill(classes.point_start.begin(), classes.point_start.end() - 1);
  for (std::size_t i = 0; i < inputs.obstacles.size(); ++i) {
    if (!blocks(i)) continue;
    const MapObstacle& o = inputs.obstacles[i];
    classes.xs[fill[o.cell]] = o.x;
    classes.ys[fill[o.cell]++] = o.y;
  }
  for (std::size_t i = 0; i < drops.cells.size(); ++i) {
    classes.xs[fill[drops.cells[i]]] = drops.positions[i].x();
    classes.ys[fill[drops.cells[i]]++] = drops.positions[i].y();
  }
  return classes;
}

CellClasses withSparseBlocked(const CellClasses& classes) {
  CellClasses blocked = classes;
  for (std::size_t cell = 0; cell < classes.sparse.size(); ++cell) {
    if (!classes.sparse[cell]) continue;
    blocked.state[cell] = CellState::kBlocked;
    blocked.reason[cell] = CellReason::kSparse;
    blocked.blocked_by_points_only[cell] = 0;
  }
  return blocked;
}

}  // namespace clearway::detail
