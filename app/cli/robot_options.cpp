#include "robot_options.h"

#include <stdexcept>

namespace clearway::cli {

std::set<std::string> withRobotOptions(std::set<std::string> options) {
  options.insert({"robot-width", "robot-length", "robot-height", "max-step", "max-slope",
                  "max-stair-rise", "max-stair-slope", "params", "method"});
  return options;
}

SegmentationParams paramsFromArguments(const Arguments& arguments) {
  SegmentationParams params;
  if (const auto file = arguments.option("params")) {
    try {
      params = loadParams(*file);
    } catch (const std::invalid_argument& error) {
      throw UsageError(error.what());
    }
  }
  params.robot.width = arguments.number("robot-width", params.robot.width, 0.05, 10.0);
  params.robot.length = arguments.number("robot-length", params.robot.length, 0.05, 20.0);
  params.robot.height = arguments.number("robot-height", params.robot.height, 0.05, 10.0);
  params.robot.max_step = arguments.number("max-step", params.robot.max_step, 0.0, 2.0);
  params.ground.max_slope_deg =
      arguments.number("max-slope", params.ground.max_slope_deg, 0.0, 89.0);
  params.robot.max_stair_rise =
      arguments.number("max-stair-rise", params.robot.max_stair_rise, 0.0, 1.0);
  params.robot.max_stair_slope_deg =
      arguments.number("max-stair-slope", params.robot.max_stair_slope_deg, 0.0, 89.0);
  if (const auto method = arguments.option("method")) {
    if (*method == "hough")
      params.lines.method = LineMethod::kHough;
    else if (*method == "split-and-merge")
      params.lines.method = LineMethod::kSplitAndMerge;
    else
      throw UsageError("--method is split-and-merge or hough");
  }
  params.robot.name = presetOrCustomName(params.robot);
  if (const auto reasons = params.validate(); !reasons.empty()) throw UsageError(reasons.front());
  return params;
}

}  // namespace clearway::cli
