#pragma once

// Command-line options shared by commands that run the pipeline: the robot and the parameters.

#include <set>
#include <string>

#include "arguments.h"
#include "clearway/segmentation/params.h"

namespace clearway::cli {

std::set<std::string> withRobotOptions(std::set<std::string> options);
// --params FILE first, then --robot-width/--robot-length/--robot-height/--max-step/--max-slope,
// --max-stair-rise/--max-stair-slope and --method; throws UsageError with the validation reason
// when the result is invalid.
SegmentationParams paramsFromArguments(const Arguments& arguments);

}  // namespace clearway::cli
