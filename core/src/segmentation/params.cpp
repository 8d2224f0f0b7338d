#include "clearway/segmentation/params.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string_view>
#include <variant>

#include "../io/strict_json.h"
#include "clearway/io/file_util.h"
#include "clearway/io/scan_error.h"

namespace clearway {
namespace {

// One numeric parameter: where it lives, what it means, what values make sense.
using Field = std::variant<double*, int*>;
struct Entry {
  const char* key;
  const char* description;
  double minimum;
  double maximum;
  Field (*field)(SegmentationParams&);
};

const std::vector<Entry>& entries() {
  static const std::vector<Entry> kEntries = {
      {"scan.self_hit_radius", "Returns closer than this to the scanner are the robot itself [m]",
       0.0, 5.0, [](SegmentationParams& p) -> Field { return &p.scan.self_hit_radius; }},
      {"lines.max_deviation", "Split a segment where a point is this far from it [m]", 0.001, 1.0,
       [](SegmentationParams& p) -> Field { return &p.lines.max_deviation; }},
      {"lines.deviation_per_metre", "Extra split distance per metre of range [m/m]", 0.0, 0.1,
       [](SegmentationParams& p) -> Field { return &p.lines.deviation_per_metre; }},
      {"lines.max_gap", "Break segments at gaps larger than this [m]", 0.01, 5.0,
       [](SegmentationParams& p) -> Field { return &p.lines.max_gap; }},
      {"lines.gap_per_metre", "Extra gap allowance per metre of range [m/m]", 0.0, 1.0,
       [](SegmentationParams& p) -> Field { return &p.lines.gap_per_metre; }},
      {"lines.min_points", "Fewest points in a segment", 2, 1000,
       [](SegmentationParams& p) -> Field { return &p.lines.min_points; }},
      {"lines.min_length", "Shortest segment [m]", 0.0, 10.0,
       [](SegmentationParams& p) -> Field { return &p.lines.min_length; }},
      {"lines.hough_angle_step_deg", "Hough angle resolution [deg]", 0.1, 10.0,
       [](SegmentationParams& p) -> Field { return &p.lines.hough_angle_step_deg; }},
      {"lines.hough_distance_step", "Hough distance resolution [m]", 0.005, 0.5,
       [](SegmentationParams& p) -> Field { return &p.lines.hough_distance_step; }},
      {"clustering.neighbour_lines", "Scan lines ahead a segment is compared with", 1, 50,
       [](SegmentationParams& p) -> Field { return &p.clustering.neighbour_lines; }},
      {"clustering.max_angle_deg", "Largest angle between similar segments [deg]", 0.5, 90.0,
       [](SegmentationParams& p) -> Field { return &p.clustering.max_angle_deg; }},
      {"clustering.max_distance", "Largest endpoint distance of similar segments [m]", 0.01, 5.0,
       [](SegmentationParams& p) -> Field { return &p.clustering.max_distance; }},
      {"clustering.distance_per_metre", "Extra endpoint distance per metre of range [m/m]", 0.0,
       1.0, [](SegmentationParams& p) -> Field { return &p.clustering.distance_per_metre; }},
      {"clustering.plane_distance", "A segment joins a plane when this close [m]", 0.005, 1.0,
       [](SegmentationParams& p) -> Field { return &p.clustering.plane_distance; }},
      {"clustering.plane_distance_per_metre", "Extra plane distance per metre of range [m/m]", 0.0,
       0.1, [](SegmentationParams& p) -> Field { return &p.clustering.plane_distance_per_metre; }},
      {"clustering.refit_every", "Refit the plane after this many new segments", 1, 1000,
       [](SegmentationParams& p) -> Field { return &p.clustering.refit_every; }},
      {"clustering.min_segments", "Segments a plane needs (paper: 25)", 3, 10000,
       [](SegmentationParams& p) -> Field { return &p.clustering.min_segments; }},
      {"clustering.merge_angle_deg", "Merge clusters whose planes differ less than this [deg]", 0.0,
       30.0, [](SegmentationParams& p) -> Field { return &p.clustering.merge_angle_deg; }},
      {"clustering.merge_distance", "... and whose offsets differ less than this [m]", 0.0, 1.0,
       [](SegmentationParams& p) -> Field { return &p.clustering.merge_distance; }},
      {"validation.support_distance", "Supporting points lie this close to a plane [m]", 0.005, 1.0,
       [](SegmentationParams& p) -> Field { return &p.validation.support_distance; }},
      {"validation.cell_size", "Support image cell size [m]", 0.02, 2.0,
       [](SegmentationParams& p) -> Field { return &p.validation.cell_size; }},
      {"validation.min_cell_points", "Supporting points a cell needs", 1, 1000,
       [](SegmentationParams& p) -> Field { return &p.validation.min_cell_points; }},
      {"validation.min_area", "Smallest connected supported area of a real plane [m^2]", 0.0,
       1000.0, [](SegmentationParams& p) -> Field { return &p.validation.min_area; }},
      {"validation.max_image_cells", "Largest support image [cells]", 1000, 1e8,
       [](SegmentationParams& p) -> Field { return &p.validation.max_image_cells; }},
      {"validation.min_inner_fraction",
       "Share of supporting points in the inner half of the band (rejects phantom planes)", 0.0,
       1.0, [](SegmentationParams& p) -> Field { return &p.validation.min_inner_fraction; }},
      {"ground.max_slope_deg", "Steepest drivable slope [deg]", 0.0, 89.0,
       [](SegmentationParams& p) -> Field { return &p.ground.max_slope_deg; }},
      {"ground.min_scanner_height", "The scanner is at least this far above the ground [m]", -5.0,
       10.0, [](SegmentationParams& p) -> Field { return &p.ground.min_scanner_height; }},
      {"ground.estimate_up", "Estimate the up direction of scans without a pose (0: refuse)", 0, 1,
       [](SegmentationParams& p) -> Field { return &p.ground.estimate_up; }},
      {"map.resolution", "Traversability cell size [m]", 0.01, 1.0,
       [](SegmentationParams& p) -> Field { return &p.map.resolution; }},
      {"map.orientations", "Robot orientations tried over 180 deg", 1, 180,
       [](SegmentationParams& p) -> Field { return &p.map.orientations; }},
      {"map.max_triangle_edge", "Ground triangles never bridge more than this [m]", 0.05, 10.0,
       [](SegmentationParams& p) -> Field { return &p.map.max_triangle_edge; }},
      {"map.obstacle_min_height", "Points lower than this above ground are ground [m]", 0.0, 1.0,
       [](SegmentationParams& p) -> Field { return &p.map.obstacle_min_height; }},
      {"map.max_extent", "Map half-size around the scanner [m]", 1.0, 500.0,
       [](SegmentationParams& p) -> Field { return &p.map.max_extent; }},
      {"stairs.cell_size", "Stair height grid cell [m]", 0.02, 0.5,
       [](SegmentationParams& p) -> Field { return &p.stairs.cell_size; }},
      {"stairs.min_rise", "Lowest riser of a staircase [m]", 0.02, 1.0,
       [](SegmentationParams& p) -> Field { return &p.stairs.min_rise; }},
      {"stairs.max_rise", "Highest riser of a staircase [m]", 0.02, 1.0,
       [](SegmentationParams& p) -> Field { return &p.stairs.max_rise; }},
      {"stairs.min_tread", "Shortest tread of a staircase [m]", 0.05, 2.0,
       [](SegmentationParams& p) -> Field { return &p.stairs.min_tread; }},
      {"stairs.max_tread", "Longest tread of a staircase [m]", 0.05, 2.0,
       [](SegmentationParams& p) -> Field { return &p.stairs.max_tread; }},
      {"stairs.min_steps", "Fewest risers of a staircase", 2, 100,
       [](SegmentationParams& p) -> Field { return &p.stairs.min_steps; }},
      {"stairs.min_width", "Narrowest staircase [m]", 0.05, 20.0,
       [](SegmentationParams& p) -> Field { return &p.stairs.min_width; }},
      {"stairs.max_distance", "Stairs are looked for this far from the scanner [m]", 1.0, 500.0,
       [](SegmentationParams& p) -> Field { return &p.stairs.max_distance; }},
      {"robot.width", "Robot width [m]", 0.05, 10.0,
       [](SegmentationParams& p) -> Field { return &p.robot.width; }},
      {"robot.length", "Robot length [m]", 0.05, 20.0,
       [](SegmentationParams& p) -> Field { return &p.robot.length; }},
      {"robot.height", "Robot height [m]", 0.05, 10.0,
       [](SegmentationParams& p) -> Field { return &p.robot.height; }},
      {"robot.max_step", "Highest obstacle the robot drives over [m]", 0.0, 2.0,
       [](SegmentationParams& p) -> Field { return &p.robot.max_step; }},
      {"robot.mount_x", "Scanner position on the robot, forward of its centre [m]", -10.0, 10.0,
       [](SegmentationParams& p) -> Field { return &p.robot.mount_x; }},
      {"robot.mount_y", "Scanner position on the robot, left of its centre [m]", -10.0, 10.0,
       [](SegmentationParams& p) -> Field { return &p.robot.mount_y; }},
      {"robot.mount_yaw_deg", "Scanner x axis turned from the robot's heading [deg]", -180.0, 180.0,
       [](SegmentationParams& p) -> Field { return &p.robot.mount_yaw_deg; }},
      {"robot.max_stair_rise", "Highest stair riser the robot climbs [m]", 0.0, 1.0,
       [](SegmentationParams& p) -> Field { return &p.robot.max_stair_rise; }},
      {"robot.max_stair_slope_deg", "Steepest flight of stairs the robot climbs [deg]", 0.0, 89.0,
       [](SegmentationParams& p) -> Field { return &p.robot.max_stair_slope_deg; }},
  };
  return kEntries;
}

const Entry& entryFor(const std::string& key) {
  for (const Entry& entry : entries())
    if (key == entry.key) return entry;
  throw std::invalid_argument("unknown parameter '" + key + "'");
}

bool isInteger(const Entry& entry) {
  SegmentationParams scratch;
  return std::holds_alternative<int*>(entry.field(scratch));
}

}  // namespace

std::string readableNumber(double value) {
  // Shortest text that reads back as the same double: 1e+300, 0.005, 4294967298 (std::to_string
  // would print 1e-300 as 0.000000).
  char text[32];
  const auto [end, error] = std::to_chars(text, text + sizeof text, value);
  return error == std::errc() ? std::string(text, end) : std::string("?");
}

double parameterValue(const SegmentationParams& params, const std::string& key) {
  // The table hands out pointers into a params object; reading through them changes nothing.
  const Field field = entryFor(key).field(const_cast<SegmentationParams&>(params));
  return std::visit([](auto* value) { return double(*value); }, field);
}

void setParameterValue(SegmentationParams& params, const std::string& key, double value) {
  const Field field = entryFor(key).field(params);
  if (auto* integer = std::get_if<int*>(&field)) {
    // A cast would wrap 4294967298 into 2; a value no int holds is refused, one an int holds but
    // the range does not is left for validate() to name.
    if (!(value >= double(std::numeric_limits<int>::min()) &&
          value <= double(std::numeric_limits<int>::max())))
      throw std::invalid_argument(key + " = " + readableNumber(value) + " is outside " +
                                  readableNumber(entryFor(key).minimum) + " .. " +
                                  readableNumber(entryFor(key).maximum));
    if (value != std::round(value))
      throw std::invalid_argument(key + " = " + readableNumber(value) + " is not a whole number");
    **integer = int(value);
  } else {
    *std::get<double*>(field) = value;
  }
}

std::vector<ParameterInfo> describeParameters() {
  const SegmentationParams defaults;
  std::vector<ParameterInfo> infos;
  for (const Entry& entry : entries())
    infos.push_back({entry.key, entry.description, entry.minimum, entry.maximum,
                     parameterValue(defaults, entry.key), isInteger(entry)});
  return infos;
}

std::vector<std::string> SegmentationParams::validate() const {
  std::vector<std::string> reasons;
  for (const Entry& entry : entries()) {
    const double value = parameterValue(*this, entry.key);
    if (!std::isfinite(value) || value < entry.minimum || value > entry.maximum)
      reasons.push_back(std::string(entry.key) + " = " + readableNumber(value) + " is outside " +
                        readableNumber(entry.minimum) + " .. " + readableNumber(entry.maximum));
  }
  if (robot.max_step >= robot.height)
    reasons.push_back("robot.max_step must be lower than robot.height");
  if (map.resolution * 4 > std::min(robot.width, robot.length))
    reasons.push_back("a robot " + readableNumber(std::min(robot.width, robot.length)) +
                      " m across is too small for cells of " + readableNumber(map.resolution) +
                      " m: its width and length must be at least 4 cells (" +
                      readableNumber(4 * map.resolution) + " m), or map.resolution at most " +
                      "a quarter of them");
  if (stairs.min_rise >= stairs.max_rise)
    reasons.push_back("stairs.min_rise must be lower than stairs.max_rise");
  if (stairs.min_tread >= stairs.max_tread)
    reasons.push_back("stairs.min_tread must be shorter than stairs.max_tread");
  if (stairs.cell_size * 2 > stairs.min_tread)
    reasons.push_back("stairs.cell_size must be at most half of stairs.min_tread");
  if (validation.support_distance < 0.5 * clustering.plane_distance)
    reasons.push_back(
        "validation.support_distance should not be much tighter than clustering.plane_distance");
  return reasons;
}

std::vector<RobotParams> robotPresets() {
  return {{"LMF smallest", 0.85, 1.2, 1.5, 0.1},
          {"LMF arm out (wide)", 1.0, 1.2, 1.5, 0.1},
          {"LMF arm raised (tall)", 0.85, 1.2, 2.1, 0.1}};
}

std::string presetOrCustomName(const RobotParams& robot) {
  for (const RobotParams& preset : robotPresets())
    if (preset.name == robot.name &&
        (preset.width != robot.width || preset.length != robot.length ||
         preset.height != robot.height || preset.max_step != robot.max_step))
      return "custom";
  return robot.name;
}

nlohmann::json toJson(const SegmentationParams& params) {
  nlohmann::json json;
  for (const Entry& entry : entries()) {
    const std::string key = entry.key;
    const auto dot = key.find('.');
    const double value = parameterValue(params, key);
    if (isInteger(entry)) {
      json[key.substr(0, dot)][key.substr(dot + 1)] = std::lround(value);
    } else {
      json[key.substr(0, dot)][key.substr(dot + 1)] = value;
    }
  }
  json["lines"]["method"] = params.lines.method == LineMethod::kHough ? "hough" : "split_and_merge";
  json["robot"]["name"] = params.robot.name;
  return json;
}

SegmentationParams paramsFromJson(const nlohmann::json& json) {
  if (!json.is_object()) throw std::invalid_argument("parameters must be a JSON object");
  SegmentationParams params;
  for (const auto& [section, values] : json.items()) {
    // Named as what it is: "'robto' must be an object" sent the reader to the wrong fault.
    const std::string prefix = section + ".";  // a structured binding: not for a lambda in clang 14
    const bool known_section = std::any_of(entries().begin(), entries().end(), [&](const Entry& e) {
      return std::string_view(e.key).starts_with(prefix);
    });
    if (!known_section) throw std::invalid_argument("unknown parameter section '" + section + "'");
    if (!values.is_object()) throw std::invalid_argument("'" + section + "' must be an object");
    for (const auto& [name, value] : values.items()) {
      const std::string key = section + "." + name;
      if ((key == "lines.method" || key == "robot.name") && !value.is_string())
        throw std::invalid_argument(key + " must be text, not " + value.dump());
      if (key == "lines.method") {
        const std::string method = value.get<std::string>();
        if (method == "hough")
          params.lines.method = LineMethod::kHough;
        else if (method == "split_and_merge")
          params.lines.method = LineMethod::kSplitAndMerge;
        else
          throw std::invalid_argument("lines.method must be split_and_merge or hough");
        continue;
      }
      if (key == "robot.name") {
        params.robot.name = value.get<std::string>();
        continue;
      }
      entryFor(key);  // "unknown parameter", before what its value is (not "must be a number")
      if (!value.is_number()) throw std::invalid_argument(key + " must be a number");
      setParameterValue(params, key, value.get<double>());
    }
  }
  return params;
}

// A parameter file is a few kilobytes; one much larger is something else.
constexpr std::uintmax_t kLargestParamsFile = 1 << 20;

SegmentationParams loadParams(const std::filesystem::path& file) {
  std::string text;
  try {
    // A pipe waited for ever and a folder said "basic_filebuf::underflow" without the file's name.
    text = readWholeFile(file, kLargestParamsFile);
  } catch (const ScanError& error) {
    throw std::invalid_argument(error.what());
  }
  try {
    SegmentationParams params = paramsFromJson(detail::parseStrictJson(text));
    if (const auto reasons = params.validate(); !reasons.empty())
      throw std::invalid_argument(reasons.front());
    return params;
  } catch (const nlohmann::json::exception& error) {
    throw std::invalid_argument(file.string() + ": " + error.what());
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument(file.string() + ": " + error.what());
  }
}

void saveParams(const SegmentationParams& params, const std::filesystem::path& file) {
  writeTextFileAtomically(file, toJson(params).dump(2) + "\n");
}

}  // namespace clearway
