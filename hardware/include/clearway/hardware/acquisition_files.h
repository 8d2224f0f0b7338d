#pragma once

// The files an acquisition leaves beside SCAN.pcd: SCAN.journal while it runs (scan_journal.h),
// then the scan (SCAN.pcd when complete, SCAN.partial.pcd when not), SCAN.pose.json (where the
// scanner was, when a pose source was given) and SCAN.acquisition.json (how the acquisition went:
// lines received, dropped, why it ended). Every file is written atomically.

#include <filesystem>
#include <string>
#include <vector>

#include "clearway/hardware/serial_acquisition.h"

namespace clearway::hardware {

std::filesystem::path journalPathFor(const std::filesystem::path& scan);      // SCAN.journal
std::filesystem::path partialPathFor(const std::filesystem::path& scan);      // SCAN.partial.pcd
std::filesystem::path poseSidecarPathFor(const std::filesystem::path& scan);  // SCAN.pose.json
std::filesystem::path reportPathFor(const std::filesystem::path& scan);  // SCAN.acquisition.json

// Checked before scanning, so no scan is lost to a typo: the name ends in .pcd, its folder
// exists, is a folder and is writable, and neither the scan nor its SCAN.partial.pcd exists (an
// acquired scan is never written over). Empty when fine, else the reason naming the path.
std::string checkOutputPath(const std::filesystem::path& scan);

// A serial port an acquisition is given: the option that named it, the device, the path.
struct NamedPort {
  std::string option;  // "--lms"
  std::string device;  // "the laser scanner"
  std::string path;
};
// Checked before any port is opened: every device has a port of its own. Two paths are the same
// port when their canonical paths are (a /dev/serial/by-id/ link and its /dev/ttyUSB0) or they
// name the same file. Empty when fine, else the reason naming both options, e.g. "the same port
// was given for --lms and --turntable (/dev/ttyUSB0): the laser scanner and the turntable each
// need a port of their own".
std::string checkDistinctPorts(const std::vector<NamedPort>& ports);

// {"version":1, "world_from_scanner": {"translation":[x,y,z], "rotation_wxyz":[w,x,y,z]},
//  "source": "arm"|"mounting", "arm_tilt_deg": .., "arm_roll_deg": .., "time": ISO 8601}
std::string poseSidecarJson(const PoseReading& pose);
// What SCAN.acquisition.json says about an acquisition saved as `saved`.
std::string acquisitionReportJson(const Acquisition& acquisition,
                                  const std::filesystem::path& saved);

// Whether a scan on disk is a partial acquisition: what SCAN.acquisition.json beside it says
// ("complete", and "reason" when it is not), else what its name says (SCAN.partial.pcd from
// `acquire`, ...-partial.pcd from the console's Scanner panel and `serve`). An unclosed turn alone
// does not say it: a sector may be what the operator asked for (`acquire --lines N`).
struct ScanCompleteness {
  bool partial = false;
  std::string reason;  // why the acquisition ended early, when its record says; may be empty
};
ScanCompleteness scanCompleteness(const std::filesystem::path& scan);

// Saves the scan to `file`, its pose sidecar (when the pose is known) and its report. Throws
// ScanError when a file cannot be written.
void saveAcquisition(const Acquisition& acquisition, const std::filesystem::path& file);

}  // namespace clearway::hardware
