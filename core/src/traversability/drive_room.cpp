#include "drive_room.h"

#include <array>
#include <atomic>
#include <cmath>
#include <vector>

#include "../segmentation/parallel.h"
#include "cell_classes.h"
#include "clearway/traversability/reachability.h"
#include "footprints.h"

namespace clearway::detail {
namespace {

// The heading's line is sampled every half cell: no cell it crosses is skipped for long.
constexpr double kSampleCells = 0.5;

}  // namespace

void markFitsWithoutRoomToDrive(TraversabilityMap& map, const CellClasses& classes,
                                const Footprints& footprints, const FootprintTester& tester,
                                std::vector<std::uint8_t>& pose_fits, const RobotParams& robot,
                                int threads) {
  const MapGrid& grid = map.grid;
  const std::size_t orientations = map.yaws.size();
  // Turned across a passage narrower than its width, the robot has less than this to drive in.
  // One cell more: a cell fits where the box fits anywhere within it (up to 0.4 cells off its
  // centre at either end of the run), and the line is sampled every half cell.
  const double room_cells = (robot.width - robot.length) / grid.resolution + 1.0;
  if (room_cells <= 1.0 || orientations == 0 || pose_fits.size() != grid.cells() * orientations)
    return;
  const TestRadii radii(footprints);
  // The tests of one pose, as the placement makes them, each made once: what a test finds is
  // recorded in `pose_fits` (several threads may make the same test and store the same answer).
  auto fits = [&](const Eigen::Vector2i& at, std::size_t k) {
    if (!grid.inside(at.x(), at.y())) return false;
    const std::size_t cell = grid.index(at.x(), at.y());
    const CellState state = classes.state[cell];
    if (state == CellState::kBlocked) return false;
    // An unobserved cell the exact test tolerates (a gap between a sparse scan's lines) does not
    // stop the run; the placement made no test there to record.
    if (state == CellState::kUnknown)
      return tester.lenientClearance(at.x(), at.y()) >= radii.exact &&
             tester.fitsExactlyInCell(at.x(), at.y(), int(k));
    std::atomic_ref<std::uint8_t> recorded(pose_fits[cell * orientations + k]);
    const auto known = PoseFit(recorded.load(std::memory_order_relaxed));
    if (known == PoseFit::kClear || known == PoseFit::kCareful) return true;
    if (known == PoseFit::kBlocked) return false;
    const PoseFit found = testPose(tester, radii, at.x(), at.y(), int(k));
    recorded.store(std::uint8_t(found), std::memory_order_relaxed);
    return found != PoseFit::kBlocked;
  };
  // The cells the heading's line crosses from a cell's centre, forward and back, each with the
  // first sample in it (1 = half a cell on): the same for every cell, per orientation.
  struct Crossed {
    int dx, dy, sample;
  };
  const int samples = int(std::ceil(room_cells / kSampleCells));
  std::vector<std::array<std::vector<Crossed>, 2>> lines(orientations);
  for (std::size_t k = 0; k < orientations; ++k)
    for (std::size_t way = 0; way < 2; ++way) {
      const double sign = way == 0 ? 1.0 : -1.0;
      const double dx = sign * kSampleCells * std::cos(map.yaws[k]),
                   dy = sign * kSampleCells * std::sin(map.yaws[k]);
      std::vector<Crossed>& crossed = lines[k][way];
      for (int i = 1; i <= samples; ++i) {
        // The centre lies half a cell into its cell.
        const int column = int(std::floor(0.5 + i * dx)), row = int(std::floor(0.5 + i * dy));
        if ((column == 0 && row == 0) ||
            (!crossed.empty() && crossed.back().dx == column && crossed.back().dy == row))
          continue;
        crossed.push_back({column, row, i});
      }
    }
  // Whether the box fits all along its heading over room_cells, forward and back from the cell.
  auto roomToDrive = [&](int column, int row, std::size_t k) {
    // How many samples the box fits at going one way, up to `most`.
    auto run = [&](const std::vector<Crossed>& crossed, int most) {
      for (const Crossed& c : crossed) {
        if (c.sample > most) return most;
        if (!fits(Eigen::Vector2i(column + c.dx, row + c.dy), k)) return c.sample - 1;
      }
      return most;
    };
    const int forward = run(lines[k][0], samples);
    return forward + run(lines[k][1], samples - forward) >= samples;
  };
  // Nothing the exact test minds lies within this of the cell (its lenient clearance): the box
  // then fits all along the run of room_cells centred on the cell, whose sweep is a square of
  // the robot's width (the length plus the run) and half a cell more along it; plus a cell and a
  // half for where a blocking cell's points lie in it and where in its cell a sample lies.
  const double open =
      std::hypot(robot.width / 2 / grid.resolution + 0.5, robot.width / 2 / grid.resolution) + 1.5;
  // Whether in some orientation its box fits in at the cell the robot can drive there: the
  // label's orientation first (the first that fitted), then the others.
  auto roomAt = [&](int column, int row) {
    if (tester.lenientClearance(column, row) > open) return true;
    const std::uint8_t labelled = map.orientation[grid.index(column, row)];
    if (labelled != kNoOrientation && roomToDrive(column, row, labelled)) return true;
    for (std::size_t k = 0; k < orientations; ++k)
      if (k != labelled && fits(Eigen::Vector2i(column, row), k) && roomToDrive(column, row, k))
        return true;
    return false;
  };
  parallelChunks(
      std::size_t(grid.height), threads, [&](std::size_t begin, std::size_t end, std::size_t) {
        for (auto row = int(begin); row < int(end); ++row)
          for (int column = 0; column < grid.width; ++column) {
            const std::size_t cell = grid.index(column, row);
            if (!robotFits(CellLabel(map.labels[cell])) || map.reach[cell] || roomAt(column, row))
              continue;
            map.labels[cell] = std::uint8_t(CellLabel::kImpassable);
            map.reasons[cell] = std::uint8_t(CellReason::kTooNarrow);
            map.orientation[cell] = kNoOrientation;
          }
      });
}

}  // namespace clearway::detail
