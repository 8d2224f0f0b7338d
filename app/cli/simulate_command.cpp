#include <chrono>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <stdexcept>

#include "arguments.h"
#include "clearway/io/scan_io.h"
#include "clearway/pose.h"
#include "clearway/sim/builtin_scenes.h"
#include "clearway/sim/ground_truth_io.h"
#include "clearway/sim/rosi_simulator.h"
#include "clearway/sim/scene_io.h"
#include "commands.h"

namespace clearway::cli {
namespace {

Eigen::Vector3d parseVector(const std::string& name, const std::string& text) {
  std::istringstream stream(text);
  Eigen::Vector3d v;
  char comma1 = 0, comma2 = 0;
  if (!(stream >> v.x() >> comma1 >> v.y() >> comma2 >> v.z()) || comma1 != ',' || comma2 != ',')
    throw UsageError("--" + name + " '" + text + "' is not X,Y,Z");
  return v;
}

Eigen::Vector3d parseAxis(const std::string& text) {
  if (text == "up") return Eigen::Vector3d::UnitZ();
  if (text == "down") return -Eigen::Vector3d::UnitZ();
  if (text == "forward") return Eigen::Vector3d::UnitX();
  if (text == "side") return Eigen::Vector3d::UnitY();
  const auto axis = unitDirection(parseVector("axis", text));
  if (!axis) throw UsageError("--axis must not be zero");
  return *axis;
}

const std::set<std::string> kSceneOptions = {"door-width", "door-height", "ramp-slope",
                                             "stair-rise", "stair-tread"};

// The built-in scenes each option shapes (the doorways scene's doors have their own widths,
// 0.7-1.3 m): given for another scene, an option would be ignored without a word.
const std::map<std::string, std::set<std::string>> kScenesOfOption = {
    {"door-width", {"garage"}},
    {"door-height", {"garage"}},
    {"ramp-slope", {"hallway"}},
    {"stair-rise", {"hallway", "stairwell"}},
    {"stair-tread", {"hallway", "stairwell"}}};

void refuseOptionsTheSceneIgnores(const Arguments& arguments, const std::string& name_or_file) {
  for (const auto& [option, scenes] : kScenesOfOption) {
    if (!arguments.option(option) || scenes.contains(name_or_file)) continue;
    std::string names;
    for (const auto& scene : scenes)
      names += (names.empty() ? "" : ", ") + scene;
    throw UsageError("--" + option + " shapes only the built-in " + names + " scene" +
                     (scenes.size() > 1 ? "s" : "") + ", not '" + name_or_file + "'");
  }
}

sim::Scene sceneFromArguments(const Arguments& arguments, const std::string& name_or_file) {
  refuseOptionsTheSceneIgnores(arguments, name_or_file);
  sim::SceneParameters parameters;
  parameters.door_width = arguments.number("door-width", parameters.door_width, 0.1, 10.0);
  parameters.door_height = arguments.number("door-height", parameters.door_height, 0.1, 10.0);
  parameters.ramp_slope_deg = arguments.number("ramp-slope", parameters.ramp_slope_deg, 1.0, 60.0);
  parameters.stair_rise = arguments.number("stair-rise", parameters.stair_rise, 0.02, 1.0);
  parameters.stair_tread = arguments.number("stair-tread", parameters.stair_tread, 0.05, 2.0);
  if (const auto scene = sim::builtinScene(name_or_file, parameters)) return *scene;
  if (name_or_file.ends_with(".json")) return sim::loadScene(name_or_file);
  std::string names;
  for (const auto& name : sim::builtinSceneNames())
    names += " " + name;
  throw UsageError("unknown scene '" + name_or_file + "' (built-in:" + names +
                   ", or a .json file)");
}

std::set<std::string> withSceneOptions(std::set<std::string> options) {
  options.insert(kSceneOptions.begin(), kSceneOptions.end());
  return options;
}

}  // namespace

int runSimulate(const std::vector<std::string>& words) {
  const Arguments arguments(
      words, {"mixed-pixels"},
      withSceneOptions({"lines", "speed", "axis", "axis-roll", "tilt", "position", "seed", "noise",
                        "dropout", "max-range", "o", "output", "encoding"}));
  arguments.expectPositional(1, "one scene: clearway-cli simulate SCENE -o FILE.pcd");
  const auto output = arguments.option("o") ? arguments.option("o") : arguments.option("output");
  if (!output) throw UsageError("-o FILE.pcd is required");
  const sim::Scene scene = sceneFromArguments(arguments, arguments.positional()[0]);

  sim::SensorModel sensor;
  if (arguments.option("speed"))
    sensor.lines = sim::SensorModel::linesForSpeed(arguments.number("speed", 0, 0.1, 3600));
  sensor.lines = int(arguments.integer("lines", sensor.lines, 1, 2'000'000));
  sensor.seed = std::uint32_t(arguments.integer("seed", sensor.seed, 0, 4'294'967'295L));
  sensor.range_noise_sigma = arguments.number("noise", sensor.range_noise_sigma, 0.0, 1.0);
  sensor.max_range = arguments.number("max-range", sensor.max_range, 0.5, 1000.0);
  sensor.mixed_pixels = arguments.flag("mixed-pixels");
  sensor.dropout = arguments.number("dropout", sensor.dropout, 0.0, 0.99);

  sim::ScannerPlacement placement = sim::defaultPlacement(scene);
  if (const auto axis = arguments.option("axis")) placement.axis = parseAxis(*axis);
  if (const auto position = arguments.option("position"))
    placement.position = parseVector("position", *position);
  placement.axis_roll_deg = arguments.number("axis-roll", 0.0, -360.0, 360.0);
  if (arguments.option("tilt")) {
    // Tilt the axis sideways (about the world x axis), as when the arm rolls the scanner.
    const double tilt = arguments.number("tilt", 0.0, -90.0, 90.0) * M_PI / 180.0;
    placement.axis = Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitX()) * placement.axis;
  }

  PcdEncoding encoding = PcdEncoding::kBinaryCompressed;
  if (const auto name = arguments.option("encoding")) {
    if (*name == "ascii")
      encoding = PcdEncoding::kAscii;
    else if (*name == "binary")
      encoding = PcdEncoding::kBinary;
    else if (*name != "binary_compressed")
      throw UsageError("--encoding is ascii, binary or binary_compressed");
  }

  const auto start = std::chrono::steady_clock::now();
  const sim::SimulatedScan simulated = [&] {
    try {
      return sim::simulateRosi(scene, sensor, placement);
    } catch (const std::invalid_argument& error) {  // the placement the options gave
      throw UsageError(error.what());
    }
  }();
  const double simulate_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  const std::filesystem::path scan_file = *output;
  saveRosiPcd(simulated.scan, scan_file, encoding);
  const auto truth_file = sim::truthPathFor(scan_file);
  sim::saveGroundTruth(simulated.truth, truth_file, scan_file.filename().string());
  std::cout << "simulated " << scene.name << ": " << simulated.scan.lines.size() << " lines x "
            << sensor.points_per_line << " points (" << simulated.scan.validCount()
            << " returns) in " << simulate_ms << " ms\n"
            << "scan:  " << scan_file.string() << "\ntruth: " << truth_file.string() << "\n";
  return 0;
}

int runScene(const std::vector<std::string>& words) {
  const Arguments arguments(words, {"list"}, withSceneOptions({"o", "output"}));
  if (arguments.flag("list")) {
    for (const auto& name : sim::builtinSceneNames())
      std::cout << name << ": " << sim::builtinScene(name)->description << "\n";
    return 0;
  }
  arguments.expectPositional(1, "one scene: clearway-cli scene NAME -o FILE.json, or --list");
  const sim::Scene scene = sceneFromArguments(arguments, arguments.positional()[0]);
  const auto output = arguments.option("o") ? arguments.option("o") : arguments.option("output");
  if (output) {
    sim::saveScene(scene, *output);
  } else {
    std::cout << sim::sceneToJson(scene).dump(2) << "\n";
  }
  return 0;
}

}  // namespace clearway::cli
