#pragma once

// One source of truth for every threshold of the pipeline (docs/ALGORITHM.md): nested per stage,
// defaults from the paper where it gives them, validate() with readable reasons, JSON load/save.
// The GUI's parameter dialog and the CLI flags read ranges from describeParameters().

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace clearway {

enum class LineMethod { kSplitAndMerge, kHough };

struct LineParams {
  LineMethod method = LineMethod::kSplitAndMerge;
  double max_deviation = 0.03;         // split where a point is this far from the chord [m] ...
  double deviation_per_metre = 0.004;  // ... plus this much per metre of range
  double max_gap = 0.25;               // a break between neighbours larger than this ... [m]
  double gap_per_metre = 0.05;         // ... plus this much per metre of range splits a run
  int min_points = 5;                  // shortest segment, in points
  double min_length = 0.10;            // shortest segment [m]
  double hough_angle_step_deg = 1.0;   // Hough accumulator resolution
  double hough_distance_step = 0.02;   // [m]
};

struct ClusterParams {
  int neighbour_lines = 3;           // segments are compared with this many following lines
  double max_angle_deg = 15.0;       // direction difference of similar segments
  double max_distance = 0.15;        // endpoint distance of similar segments [m] ...
  double distance_per_metre = 0.03;  // ... plus this much per metre of range
  double plane_distance = 0.05;      // a segment joins a plane if its ends are this close [m] ...
  double plane_distance_per_metre = 0.005;
  int refit_every = 5;           // refit the plane after this many new segments (paper)
  int min_segments = 8;          // a plane needs this many segments (paper: 25 at RoSi density)
  double merge_angle_deg = 4.0;  // coplanar clusters are merged ...
  double merge_distance = 0.06;  // ... when this close [m]
};

struct ValidationParams {
  double support_distance = 0.05;   // supporting points lie this close to the plane [m]
  double cell_size = 0.2;           // support image cell (paper: ~0.2 m)
  int min_cell_points = 2;          // a cell with this many supporting points counts
  double min_area = 0.6;            // the largest connected supported area must reach this [m^2]
  int max_image_cells = 4'000'000;  // support images larger than this are clipped
  // A real plane's support crowds near it (range noise); a phantom cutting a zig-zag (the nosings
  // of a staircase) spreads evenly over the band. This share must lie in the band's inner half.
  double min_inner_fraction = 0.65;
};

struct GroundParams {
  double max_slope_deg = 45.0;  // steepest drivable slope (the LMF: 45 deg)
  // The scanner (the frame's origin) must be at least this far above a ground plane [m]. Negative:
  // some files put their origin at ground level (3DTK, octomap); a ceiling is always higher.
  double min_scanner_height = -0.3;
  // A scan without a pose gets its up direction estimated from its planes (1), or is refused (0).
  int estimate_up = 1;
};

struct ScanParams {
  // Returns closer than this to the scanner are the robot's own body or the mount [m].
  double self_hit_radius = 0.3;
};

struct MapParams {
  double resolution = 0.05;           // traversability cell [m]
  int orientations = 12;              // box orientations tried over 180 deg (every 15 deg)
  double max_triangle_edge = 1.0;     // ground triangles never bridge more than this [m]
  double obstacle_min_height = 0.04;  // points lower than this above ground are ground noise [m]
  double max_extent = 60.0;           // map half-size limit around the scanner [m]
};

// Stairs: regular risers and treads (docs/ALGORITHM.md, "Stairs"). Ranges of real stairs.
struct StairParams {
  double cell_size = 0.1;  // height grid cell; at most half the shortest tread [m]
  double min_rise = 0.1;   // riser height range [m] ...
  double max_rise = 0.25;
  double min_tread = 0.2;  // ... tread depth range [m]
  double max_tread = 0.45;
  int min_steps = 3;           // a staircase has at least this many risers
  double min_width = 0.3;      // risers shorter than this are not stairs [m]
  double max_distance = 20.0;  // stairs are looked for this far from the scanner [m]
};

struct RobotParams {
  std::string name = "LMF smallest";
  double width = 0.85;    // [m]
  double length = 1.2;    // [m]
  double height = 1.5;    // [m]
  double max_step = 0.1;  // obstacles up to this height are "probably passable" [m]
  // Where the scanner sits on the robot (robot_from_scanner, seen from above): the scanner's
  // position in the robot's frame (x forward, y left) and how far its x axis is turned from the
  // robot's. Places the robot on the map around the scanner's foot.
  double mount_x = 0.0;        // [m]
  double mount_y = 0.0;        // [m]
  double mount_yaw_deg = 0.0;  // [deg]
  // Stairs it climbs: the highest riser [m] and the steepest flight [deg] (the LMF: 45 deg).
  double max_stair_rise = 0.2;
  double max_stair_slope_deg = 45.0;
};

struct SegmentationParams {
  ScanParams scan;
  LineParams lines;
  ClusterParams clustering;
  ValidationParams validation;
  GroundParams ground;
  MapParams map;
  StairParams stairs;
  RobotParams robot;

  // Empty when usable; otherwise one readable reason per bad value.
  std::vector<std::string> validate() const;
};

// Robot configurations the operator picks from.
std::vector<RobotParams> robotPresets();
// The robot's name as the operator should read it: "custom" when it carries a preset's name but
// not that preset's sizes (a preset changed on the command line or in the panel), else its own.
std::string presetOrCustomName(const RobotParams& robot);

// JSON with the same nesting as the structs; unknown keys are reported, missing keys keep defaults.
nlohmann::json toJson(const SegmentationParams& params);
SegmentationParams paramsFromJson(const nlohmann::json& json);  // throws std::invalid_argument
SegmentationParams loadParams(const std::filesystem::path& file);
void saveParams(const SegmentationParams& params, const std::filesystem::path& file);

// One entry per numeric parameter, for generated dialogs and CLI help.
struct ParameterInfo {
  std::string key;  // "map.resolution"
  std::string description;
  double minimum = 0.0;
  double maximum = 0.0;
  double default_value = 0.0;
  bool integer = false;
};
std::vector<ParameterInfo> describeParameters();
// Reads or writes one parameter by key; throws std::invalid_argument for an unknown key.
double parameterValue(const SegmentationParams& params, const std::string& key);
// Sets one parameter; throws std::invalid_argument for a whole-number parameter given a fraction
// or a value no int holds (it would wrap). Range checks are validate()'s.
void setParameterValue(SegmentationParams& params, const std::string& key, double value);

// The shortest text that reads back as `value` (1e+300, 0.005): for messages.
std::string readableNumber(double value);

}  // namespace clearway
