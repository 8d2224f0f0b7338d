#include "mount_options.h"

namespace clearway::cli {

hardware::RigidPose poseOption(const Arguments& arguments, const std::string& name,
                               const hardware::RigidPose& fallback) {
  const auto text = arguments.option(name);
  if (!text) return fallback;
  std::string error;
  const auto pose = hardware::parsePose(*text, error);
  if (!pose) throw UsageError("--" + name + ": " + error);
  return *pose;
}

std::shared_ptr<hardware::PoseSource> poseSourceOption(const Arguments& arguments) {
  if (const auto arm = arguments.option("arm"))
    return std::make_shared<hardware::ArmPoseSource>(
        *arm, poseOption(arguments, "mount", hardware::defaultToolFromScanner()));
  if (arguments.option("mount"))
    return std::make_shared<hardware::FixedMounting>(poseOption(arguments, "mount", {}));
  return nullptr;
}

std::vector<hardware::NamedPort> namedPorts(const Arguments& arguments) {
  std::vector<hardware::NamedPort> ports;
  for (const auto& [name, device] :
       {std::pair<std::string, std::string>{"lms", "the laser scanner"},
        {"turntable", "the turntable"},
        {"arm", "the arm controller"}})
    if (const auto path = arguments.option(name)) ports.push_back({"--" + name, device, *path});
  return ports;
}

}  // namespace clearway::cli
