#include "clearway/sim/ground_truth_io.h"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "clearway/io/file_util.h"
#include "clearway/io/result_manifest.h"
#include "clearway/io/scan_error.h"
#include "clearway/sim/scene_io.h"

namespace clearway::sim {
namespace {

using nlohmann::json;

// A truth file holds a class and a surface per point: a few hundred MB for 10M points.
constexpr std::uintmax_t kLargestTruthFile = 4ULL << 30;

// The truth file's layout (its "version"): a file of another is refused, not misread.
constexpr int kTruthVersion = 1;

json vectorJson(const Eigen::Vector3d& v) {
  return json::array({v.x(), v.y(), v.z()});
}
Eigen::Vector3d vectorFrom(const json& v) {
  return {v.at(0).get<double>(), v.at(1).get<double>(), v.at(2).get<double>()};
}

// The scanner's `key`: three numbers (a fourth was ignored, a word read as a malformed file).
Eigen::Vector3d scannerVector(const std::filesystem::path& file, const json& scanner,
                              const char* key) {
  const json& value = scanner.at(key);
  if (!value.is_array() || value.size() != 3 ||
      !std::all_of(value.begin(), value.end(), [](const json& v) { return v.is_number(); }))
    throw SceneError(file.string() + ": scanner." + key + " = " + value.dump().substr(0, 40) +
                     " must be [x, y, z]");
  return vectorFrom(value);
}

}  // namespace

std::filesystem::path truthPathFor(const std::filesystem::path& scan_file) {
  std::filesystem::path truth = scan_file;
  truth.replace_extension(".truth.json");
  return truth;
}

std::vector<std::pair<std::string, RobotBox>> robotPresets() {
  return {{"lmf_small", RobotBox{0.85, 1.2, 1.5, 0.1}},
          {"lmf_arm_out", RobotBox{1.0, 1.2, 1.5, 0.1}},
          {"lmf_raised", RobotBox{0.85, 1.2, 2.1, 0.1}}};
}

void saveGroundTruth(const GroundTruth& truth, const std::filesystem::path& file,
                     const std::string& scan_file_name) {
  json document;
  document["format"] = "clearway-truth";
  document["version"] = kTruthVersion;
  document["scan"] = utf8FileName(scan_file_name);  // JSON needs UTF-8; lossless for any bytes
  document["scene"] = sceneToJson(truth.scene);
  document["sensor"] = {{"lines", truth.sensor.lines},
                        {"points_per_line", truth.sensor.points_per_line},
                        {"alpha_step_deg", truth.sensor.alpha_step_deg},
                        {"range_noise_sigma", truth.sensor.range_noise_sigma},
                        {"max_range", truth.sensor.max_range},
                        {"mixed_pixels", truth.sensor.mixed_pixels},
                        {"dropout", truth.sensor.dropout},
                        {"seed", truth.sensor.seed}};
  const Eigen::Matrix4d pose = truth.placement.worldFromScanner().matrix();
  std::vector<double> row_major;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      row_major.push_back(pose(r, c));
  document["scanner"] = {{"position", vectorJson(truth.placement.position)},
                         {"axis", vectorJson(truth.placement.axis)},
                         {"axis_roll_deg", truth.placement.axis_roll_deg},
                         {"world_from_scanner", row_major}};
  json classes = json::array();
  for (PointClass c : truth.classes)
    classes.push_back(int(c));
  document["class_names"] = {"none", "ground", "wall", "ceiling", "obstacle", "stairs"};
  document["classes"] = classes;
  document["surfaces"] = truth.surfaces;
  json surfaces = json::array();
  for (const SurfaceTruth& s : truth.seen_surfaces)
    surfaces.push_back({{"id", s.id},
                        {"primitive", s.primitive},
                        {"face", s.face},
                        {"class", std::string(className(s.point_class))},
                        {"planar", s.planar},
                        {"normal", vectorJson(s.normal)},
                        {"offset", s.offset},
                        {"points", s.points}});
  document["surfaces_seen"] = surfaces;
  json reachable = json::object();
  for (const auto& [name, robot] : robotPresets()) {
    json pairs = json::array();
    for (const auto& [a, b] : reachablePlaces(truth.scene, robot))
      pairs.push_back({a, b});
    reachable[name] = {{"robot",
                        {{"width", robot.width},
                         {"length", robot.length},
                         {"height", robot.height},
                         {"max_step", robot.max_step}}},
                       {"pairs", pairs}};
  }
  document["reachable"] = reachable;
  writeTextFileAtomically(file, document.dump() + "\n");
}

GroundTruth loadGroundTruth(const std::filesystem::path& file) {
  std::string text;
  try {
    text = readWholeFile(file, kLargestTruthFile);  // not a pipe, a folder or a device
  } catch (const ScanError& error) {
    throw SceneError(error.what());
  }
  try {
    const json document = json::parse(text);
    if (document.value("format", "") != "clearway-truth")
      throw SceneError(file.string() + ": not a Clearway truth file");
    // A newer layout would be read as this one, its changes unseen.
    if (const int version = document.value("version", 0); version != kTruthVersion)
      throw SceneError(file.string() + ": truth file version " + std::to_string(version) +
                       "; this Clearway reads version " + std::to_string(kTruthVersion));
    GroundTruth truth;
    truth.scan = document.value("scan", "");
    truth.scene = sceneFromJson(document.at("scene"));
    const json& sensor = document.at("sensor");
    truth.sensor.lines = sensor.at("lines");
    truth.sensor.points_per_line = sensor.at("points_per_line");
    truth.sensor.alpha_step_deg = sensor.at("alpha_step_deg");
    truth.sensor.range_noise_sigma = sensor.at("range_noise_sigma");
    truth.sensor.max_range = sensor.at("max_range");
    truth.sensor.mixed_pixels = sensor.at("mixed_pixels");
    truth.sensor.dropout = sensor.value("dropout", 0.0);  // files from before it existed: none
    truth.sensor.seed = sensor.at("seed");
    const json& scanner = document.at("scanner");
    truth.placement.position = scannerVector(file, scanner, "position");
    truth.placement.axis = scannerVector(file, scanner, "axis");
    const json& roll = scanner.at("axis_roll_deg");
    if (!roll.is_number())
      throw SceneError(file.string() + ": scanner.axis_roll_deg = " + roll.dump().substr(0, 40) +
                       " is not a number");
    truth.placement.axis_roll_deg = roll.get<double>();
    // eval places the map by this pose: a scanner at 1e308 put every cell off the scene.
    if (const std::string problem = placementProblem(truth.placement, "scanner."); !problem.empty())
      throw SceneError(file.string() + ": " + problem);
    for (const json& value : document.at("classes")) {
      // A class of 1.5 was read as 1: only whole numbers are classes.
      if (!value.is_number_integer())
        throw SceneError(file.string() + ": class " + value.dump() + " is not a whole number");
      const auto c = value.get<std::int64_t>();
      if (c < 0 || c >= kPointClassCount) throw SceneError(file.string() + ": class out of range");
      truth.classes.push_back(PointClass(c));
    }
    truth.surfaces = document.at("surfaces").get<std::vector<std::int32_t>>();
    if (truth.surfaces.size() != truth.classes.size())
      throw SceneError(file.string() + ": classes and surfaces differ in length");
    for (const json& s : document.at("surfaces_seen")) {
      SurfaceTruth surface;
      surface.id = s.at("id");
      surface.primitive = s.at("primitive");
      surface.face = s.at("face");
      surface.point_class =
          classFromName(s.at("class").get<std::string>()).value_or(PointClass::kNone);
      surface.planar = s.at("planar");
      surface.normal = vectorFrom(s.at("normal"));
      surface.offset = s.at("offset");
      surface.points = s.at("points");
      truth.seen_surfaces.push_back(surface);
    }
    return truth;
  } catch (const nlohmann::json::exception& error) {
    throw SceneError(file.string() + ": malformed truth file (" + error.what() + ")");
  }
}

}  // namespace clearway::sim
