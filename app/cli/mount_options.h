#pragma once

// --arm PORT and --mount POSE, as acquire and serve take them: where the scanner is when each scan
// starts (docs/ARM.md). With --arm, --mount is the RoSi on the tool flange (tool_from_scanner,
// default the RoSi's own mounting); without it, --mount is the scanner on the robot
// (robot_from_scanner).

#include <memory>
#include <string>
#include <vector>

#include "arguments.h"
#include "clearway/hardware/acquisition_files.h"
#include "clearway/hardware/pose_source.h"

namespace clearway::cli {

// The pose option `name` ("tx,ty,tz,qw,qx,qy,qz"), or `fallback` when absent; UsageError when
// malformed.
hardware::RigidPose poseOption(const Arguments& arguments, const std::string& name,
                               const hardware::RigidPose& fallback);

// The arm, a fixed mounting, or nullptr when neither option is given.
std::shared_ptr<hardware::PoseSource> poseSourceOption(const Arguments& arguments);

// The ports --lms, --turntable and --arm name (those given), for hardware::checkDistinctPorts.
std::vector<hardware::NamedPort> namedPorts(const Arguments& arguments);

}  // namespace clearway::cli
