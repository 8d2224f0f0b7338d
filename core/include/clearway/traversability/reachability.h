#pragma once

// "Can it get there?" (issue: the robot's own place, reachability and a path). The robot stands
// on the map at its own pose; from there it moves its box through cells where it fits and turns
// on the spot where it fits in both headings. Cells where the box fits but that cannot be reached
// that way are told apart from the reachable ones, and a goal gets a path of robot poses.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "clearway/segmentation/params.h"
#include "clearway/segmentation/scan_analysis.h"

namespace clearway {

struct TraversabilityMap;

// The robot's pose on the map frame (metres, radians; yaw from map +x, counter-clockwise).
struct RobotPose {
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;
};

// Where the robot stands: from the sidecar's robot-frame pose when acquisition recorded one;
// otherwise around the scanner's foot by its mounting (RobotParams::mount_*), in the heading among
// `yaws` (+ the mounting's own) whose box holds the fewest measured obstacles - the robot stands
// where it fits, and a scan alone does not say which way it faces.
RobotPose robotPoseOnMap(const ScanAnalysis& analysis, const RobotParams& robot,
                         const std::vector<double>& yaws);

// How the box fits at one cell in one of the map's orientations.
enum class PoseFit : std::uint8_t {
  kUntested = 0,
  kBlocked = 1,
  kCareful = 2,  // fits only against the exact points (orange)
  kClear = 3,    // fits with half a cell to spare (green)
};

// The fit of every orientation at the cells the reachability search looked at (its reach, and
// the cells where a move of it stopped), kept for those cells only: a car-mounted
// sensor's search meets a handful of a map's cells, and a table of every pose took 14 MB on a
// KITTI frame (298k cells x 48 orientations).
class MetPoseFits {
 public:
  MetPoseFits() = default;
  MetPoseFits(std::size_t cells, std::size_t orientations)
      : orientations_(orientations), slot_(cells, kNoSlot) {}

  std::size_t orientations() const { return orientations_; }
  std::size_t cells() const { return slot_.size(); }
  std::size_t metCells() const { return orientations_ == 0 ? 0 : fits_.size() / orientations_; }
  // kUntested where the search did not meet the pose.
  PoseFit at(std::size_t cell, std::size_t k) const {
    const std::uint32_t slot = slot_[cell];
    return slot == kNoSlot ? PoseFit::kUntested
                           : PoseFit(fits_[std::size_t(slot) * orientations_ + k]);
  }
  // The cell's fits by orientation, all kUntested when it is first asked for. Cells are best
  // asked for in map order (their fits then lie in map order too).
  std::uint8_t* fitsOf(std::size_t cell) {
    if (slot_[cell] == kNoSlot) {
      slot_[cell] = std::uint32_t(metCells());
      fits_.resize(fits_.size() + orientations_, std::uint8_t(PoseFit::kUntested));
    }
    return fits_.data() + std::size_t(slot_[cell]) * orientations_;
  }

 private:
  static constexpr std::uint32_t kNoSlot = 0xFFFFFFFFU;
  std::size_t orientations_ = 0;
  std::vector<std::uint32_t> slot_;  // per cell: its place among the met cells, or kNoSlot
  std::vector<std::uint8_t> fits_;   // PoseFit per met cell and orientation
};

struct PathPose {
  double x = 0.0, y = 0.0;  // map frame [m]
  double heading_deg = 0.0;
};

struct GoalResult {
  bool reachable = false;
  std::string reason;          // why not, when not
  std::vector<PathPose> path;  // from the robot's pose to the goal, when reachable
  double length_m = 0.0;       // driven length (turns on the spot add none)
  // Of length_m, the metres over ground the map does not vouch for (orange, reason "too sparse"
  // or "not seen up to the robot's height"): the path is drivable only with care there.
  double unvouched_m = 0.0;
  // What the search minimised: metres of green driving (orange counts 3 times its length, each
  // turn step as 0.05 m of driving).
  double cost = 0.0;
};

// A* over (cell, orientation) on the fits the map recorded: prefers green over orange and
// straight runs over turns. The goal is a map position; any orientation there will do.
GoalResult planPath(const TraversabilityMap& map, double goal_x, double goal_y);

}  // namespace clearway
