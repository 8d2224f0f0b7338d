#pragma once

// "Can it get there?" (issue: the robot's own place, reachability and a path). The robot stands
// on the map at its own pose; from there it moves its box through cells where it fits and turns
// on the spot where it fits in both headings. Cells where the box fits but that cannot be reached
// that way are told apart from the reachable ones, and a goal gets a path of robot poses.

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

struct PathPose {
  double x = 0.0, y = 0.0;  // map frame [m]
  double heading_deg = 0.0;
};

struct GoalResult {
  bool reachable = false;
  std::string reason;          // why not, when not
  std::vector<PathPose> path;  // from the robot's pose to the goal, when reachable
  double length_m = 0.0;       // driven length (turns on the spot add none)
  // What the search minimised: metres of green driving (orange counts 3 times its length, each
  // turn step as 0.05 m of driving).
  double cost = 0.0;
};

// A* over (cell, orientation) on the fits the map recorded: prefers green over orange and
// straight runs over turns. The goal is a map position; any orientation there will do.
GoalResult planPath(const TraversabilityMap& map, double goal_x, double goal_y);

}  // namespace clearway
