#include "clearway/hardware/acquisition_files.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <nlohmann/json.hpp>
#include <string_view>

#include "clearway/io/file_util.h"
#include "clearway/io/scan_error.h"
#include "clearway/io/scan_io.h"

namespace clearway::hardware {
namespace {

std::filesystem::path withSuffix(const std::filesystem::path& scan, const std::string& suffix) {
  std::filesystem::path result = scan;
  result.replace_extension(suffix);
  return result;
}

}  // namespace

std::filesystem::path journalPathFor(const std::filesystem::path& scan) {
  return withSuffix(scan, ".journal");
}
std::filesystem::path partialPathFor(const std::filesystem::path& scan) {
  return withSuffix(scan, ".partial.pcd");
}
std::filesystem::path poseSidecarPathFor(const std::filesystem::path& scan) {
  return withSuffix(scan, ".pose.json");
}
std::filesystem::path reportPathFor(const std::filesystem::path& scan) {
  return withSuffix(scan, ".acquisition.json");
}

std::string checkOutputPath(const std::filesystem::path& scan) {
  if (scan.extension() != ".pcd")
    return scan.string() + ": an acquired scan is saved as PCD: give a name ending in .pcd";
  const std::filesystem::path folder =
      scan.parent_path().empty() ? std::filesystem::path(".") : scan.parent_path();
  std::error_code error;
  if (!std::filesystem::exists(folder, error))
    return "the folder " + folder.string() + " for " + scan.string() + " does not exist";
  if (!std::filesystem::is_directory(folder, error))
    return folder.string() + " (the folder for " + scan.string() + ") is not a folder";
  if (::access(folder.c_str(), W_OK | X_OK) != 0)
    return "the folder " + folder.string() + " for " + scan.string() + " is not writable";
  if (std::filesystem::is_directory(scan, error))
    return scan.string() + " is a folder, not a file name";
  // An acquired scan is never written over, complete or partial.
  for (const std::filesystem::path& existing : {scan, partialPathFor(scan)})
    if (std::filesystem::exists(existing, error))
      return existing.string() +
             " exists: a scan already acquired is never written over; give another name or move "
             "it away";
  return {};
}

std::string checkDistinctPorts(const std::vector<NamedPort>& ports) {
  auto canonical = [](const std::string& path) {
    std::error_code error;
    const std::filesystem::path resolved = std::filesystem::weakly_canonical(path, error);
    return error ? std::filesystem::path(path).lexically_normal() : resolved;
  };
  for (std::size_t a = 0; a < ports.size(); ++a) {
    for (std::size_t b = a + 1; b < ports.size(); ++b) {
      const NamedPort &first = ports[a], &second = ports[b];
      const std::filesystem::path first_port = canonical(first.path);
      const bool same_path = first_port == canonical(second.path);
      std::error_code error;
      if (!same_path && !std::filesystem::equivalent(first.path, second.path, error)) continue;
      const std::string where =
          first.path == second.path
              ? first.path
              : first.path + " and " + second.path + " are " +
                    (same_path ? "both " + first_port.string() : std::string("the same device"));
      return "the same port was given for " + first.option + " and " + second.option + " (" +
             where + "): " + first.device + " and " + second.device +
             " each need a port of their own";
    }
  }
  return {};
}

std::string poseSidecarJson(const PoseReading& pose) {
  const RigidPose& p = pose.world_from_scanner;
  nlohmann::ordered_json json;
  json["version"] = 1;
  json["world_from_scanner"] = {
      {"translation", {p.translation.x(), p.translation.y(), p.translation.z()}},
      {"rotation_wxyz", {p.rotation.w(), p.rotation.x(), p.rotation.y(), p.rotation.z()}}};
  json["source"] = pose.source;
  json["arm_tilt_deg"] = pose.arm_tilt_deg ? nlohmann::ordered_json(*pose.arm_tilt_deg) : nullptr;
  json["arm_roll_deg"] = pose.arm_roll_deg ? nlohmann::ordered_json(*pose.arm_roll_deg) : nullptr;
  json["time"] = pose.time;
  return json.dump(2) + "\n";
}

std::string acquisitionReportJson(const Acquisition& acquisition,
                                  const std::filesystem::path& saved) {
  nlohmann::ordered_json json;
  json["version"] = 1;
  json["scan"] = saved.filename().string();
  json["complete"] = acquisition.complete;
  json["reason"] = acquisition.error;
  json["lines"] = acquisition.scan.lines.size();
  json["lines_received"] = acquisition.lines_received;
  json["dropped_lines"] = acquisition.dropped_lines;
  json["untagged_lines"] = acquisition.untagged_lines;
  json["stopped_by_signal"] = acquisition.stopped;
  if (!acquisition.journal_error.empty()) {
    json["journal_error"] = acquisition.journal_error;
    json["lines_journaled"] = acquisition.lines_journaled;
  }
  json["pose_source"] = acquisition.pose ? nlohmann::ordered_json(acquisition.pose->source)
                                         : nlohmann::ordered_json(nullptr);
  return json.dump(2) + "\n";
}

void saveAcquisition(const Acquisition& acquisition, const std::filesystem::path& file) {
  saveRosiPcd(acquisition.scan, file);
  if (acquisition.pose)
    writeTextFileAtomically(poseSidecarPathFor(file), poseSidecarJson(*acquisition.pose));
  writeTextFileAtomically(reportPathFor(file), acquisitionReportJson(acquisition, file));
}

// An acquisition's record is a few hundred bytes: anything far larger is not one.
constexpr std::uintmax_t kLargestRecordBytes = 1 << 20;

ScanCompleteness scanCompleteness(const std::filesystem::path& scan) {
  ScanCompleteness completeness;
  const std::filesystem::path record = reportPathFor(scan);
  std::error_code error;
  if (std::filesystem::is_regular_file(record, error)) {
    try {
      const nlohmann::json json = nlohmann::json::parse(readWholeFile(record, kLargestRecordBytes));
      if (const auto complete = json.find("complete");
          complete != json.end() && complete->is_boolean()) {
        completeness.partial = !complete->get<bool>();
        if (const auto reason = json.find("reason");
            completeness.partial && reason != json.end() && reason->is_string())
          completeness.reason = printableText(reason->get<std::string>());
        return completeness;
      }
    } catch (const std::exception&) {
      // An unreadable record says nothing: the name still does.
    }
  }
  const std::string name = scan.filename().string();
  auto endsWith = [&name](std::string_view tail) {
    return name.size() >= tail.size() &&
           std::equal(tail.rbegin(), tail.rend(), name.rbegin(), [](char a, char b) {
             return a == std::tolower(static_cast<unsigned char>(b));
           });
  };
  completeness.partial = endsWith(".partial.pcd") || endsWith("-partial.pcd");
  return completeness;
}

}  // namespace clearway::hardware
