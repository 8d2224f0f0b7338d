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

}  // namespace clearway::cli
