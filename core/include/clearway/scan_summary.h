#pragma once

// What `clearway-cli info` and the GUI's scan panel tell about a scan.

#include <array>
#include <cstddef>
#include <optional>
#include <string>

#include "clearway/scan.h"

namespace clearway {

struct ScanSummary {
  std::string file;
  std::string format;
  std::string frame;
  std::string caution;  // what the loader could not work out (ScanMetadata::caution); empty: none
  std::size_t points = 0;        // records in the file
  std::size_t valid_points = 0;  // real returns
  std::size_t no_return = 0;
  std::size_t max_range = 0;
  std::size_t self_hits = 0;
  std::size_t scan_lines = 0;
  std::size_t points_per_line = 0;  // when organised; else the longest line
  std::size_t shortest_line = 0;
  bool organised = false;
  bool has_intensity = false;
  bool has_beta = false;
  Bounds bounds;
  std::optional<SensorPose> sensor_pose;
  std::string pose_source = "none";  // what resolveScanPose chose (pose.h)
  std::string pose_detail;
  std::string sensor;        // "rotating 2D", "multi-beam" or "unknown" (sensor_geometry.h)
  std::size_t rings = 0;     // multi-beam: the rings (its scan lines)
  bool closed_turn = false;  // rotating 2D: the lines go once around (last meets first)
  // rotating 2D: the axis its fans turn about when far from z (a nodding scanner's; x, y, z)
  std::optional<std::array<double, 3>> tilted_axis;
  double along_line_step_deg = 0.0;    // median angle between returns of a line
  double between_line_step_deg = 0.0;  // median angle between neighbouring lines
};

ScanSummary summarise(const Scan& scan);

// Human-readable, one fact per line.
std::string toText(const ScanSummary& summary);
// One JSON object; keys as in docs/FORMATS.md.
std::string toJson(const ScanSummary& summary);

}  // namespace clearway
