#include "clearway/scan_summary.h"

#include "clearway/pose.h"
#include "clearway/sensor_geometry.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "clearway/io/result_manifest.h"

namespace clearway {

ScanSummary summarise(const Scan& scan) {
  ScanSummary summary;
  summary.file = scan.metadata.source_path;
  summary.format = scan.metadata.format;
  summary.frame = scan.metadata.frame;
  summary.caution = scan.metadata.caution;
  summary.points = scan.size();
  for (PointStatus status : scan.status) {
    switch (status) {
      case PointStatus::kValid:
        ++summary.valid_points;
        break;
      case PointStatus::kNoReturn:
        ++summary.no_return;
        break;
      case PointStatus::kMaxRange:
        ++summary.max_range;
        break;
      case PointStatus::kSelfHit:
        ++summary.self_hits;
        break;
    }
  }
  summary.scan_lines = scan.lines.size();
  summary.points_per_line = scan.pointsPerLine();
  summary.shortest_line = scan.lines.empty() ? 0 : scan.lines.front().count;
  for (const ScanLine& line : scan.lines)
    summary.shortest_line = std::min(summary.shortest_line, line.count);
  summary.organised = scan.isOrganised();
  summary.has_intensity = !scan.intensity.empty();
  summary.has_beta = std::any_of(scan.lines.begin(), scan.lines.end(),
                                 [](const ScanLine& line) { return std::isfinite(line.beta); });
  summary.bounds = validBounds(scan);
  summary.sensor_pose = scan.sensor_pose;
  summary.pose_source = scan.pose_source == PoseSource::kNone && scan.sensor_pose
                            ? "file"
                            : std::string(poseSourceName(scan.pose_source));
  const SensorGeometry sensor = describeSensor(scan);
  summary.sensor = std::string(sensorKindName(sensor.kind));
  summary.rings = sensor.kind == SensorKind::kMultiBeam ? sensor.lines : 0;
  summary.closed_turn = sensor.closed_turn;
  if (sensor.tilted_axis)
    summary.tilted_axis = {sensor.tilted_axis->x(), sensor.tilted_axis->y(),
                           sensor.tilted_axis->z()};
  summary.along_line_step_deg = sensor.along_line_step * 180.0 / M_PI;
  summary.between_line_step_deg = sensor.between_line_step * 180.0 / M_PI;
  return summary;
}

std::string toText(const ScanSummary& s) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(3);
  out << "file:            " << s.file << '\n'
      << "format:          " << s.format << '\n'
      << "frame:           " << s.frame << '\n'
      << "points:          " << s.points << '\n'
      << "valid_points:    " << s.valid_points << "  (no return " << s.no_return << ", max range "
      << s.max_range << ", self hits " << s.self_hits << ")\n"
      << "scan_lines:      " << s.scan_lines << '\n'
      << "points_per_line: " << s.points_per_line
      << (s.organised
              ? ""
              : "  (longest; lines differ, shortest " + std::to_string(s.shortest_line) + ")")
      << '\n'
      << "organised:       " << (s.organised ? "yes" : "no") << '\n'
      << "intensity:       " << (s.has_intensity ? "yes" : "no") << '\n'
      << "turntable angle: " << (s.has_beta ? "per line" : "unknown") << '\n'
      << "sensor:          " << s.sensor;
  if (s.sensor == "multi-beam") out << ", rings: " << s.rings;
  if (s.closed_turn) out << ", full turn";
  if (s.tilted_axis) {
    // To the thousandth, as printed, and + 0.0: a component a hair below zero prints as 0.
    auto shown = [](double component) { return std::round(component * 1000.0) / 1000.0 + 0.0; };
    const auto& axis = *s.tilted_axis;
    out << ", fans about a tilted axis (nodding) " << shown(axis[0]) << ' ' << shown(axis[1]) << ' '
        << shown(axis[2]);
  }
  out << " (steps: " << s.along_line_step_deg << " deg along a line, " << s.between_line_step_deg
      << " deg between lines)";
  out << '\n';
  if (!s.bounds.empty())
    out << "bounds [m]:      x " << s.bounds.min.x << " .. " << s.bounds.max.x << ", y "
        << s.bounds.min.y << " .. " << s.bounds.max.y << ", z " << s.bounds.min.z << " .. "
        << s.bounds.max.z << '\n';
  out << "pose source: " << s.pose_source;
  if (!s.pose_detail.empty()) out << " (" << s.pose_detail << ")";
  if (s.pose_source == "none") out << ": the up direction will be estimated from the scan";
  out << '\n';
  if (s.sensor_pose)
    out << "sensor position: " << s.sensor_pose->position[0] << ' ' << s.sensor_pose->position[1]
        << ' ' << s.sensor_pose->position[2] << '\n';
  if (!s.caution.empty()) out << "caution:         " << s.caution << '\n';
  return out.str();
}

std::string toJson(const ScanSummary& s) {
  nlohmann::ordered_json json;
  json["file"] = utf8FileName(s.file);  // JSON needs UTF-8; lossless for any bytes
  json["format"] = s.format;
  json["frame"] = s.frame;
  json["points"] = s.points;
  json["valid_points"] = s.valid_points;
  json["invalid"] = {
      {"no_return", s.no_return}, {"max_range", s.max_range}, {"self_hit", s.self_hits}};
  json["scan_lines"] = s.scan_lines;
  json["points_per_line"] = s.points_per_line;
  json["shortest_line"] = s.shortest_line;
  json["organised"] = s.organised;
  json["has_intensity"] = s.has_intensity;
  json["has_beta"] = s.has_beta;
  json["sensor"] = s.sensor;
  if (s.sensor == "multi-beam") json["rings"] = s.rings;
  json["closed_turn"] = s.closed_turn;
  if (s.tilted_axis) json["tilted_axis"] = *s.tilted_axis;
  json["along_line_step_deg"] = s.along_line_step_deg;
  json["between_line_step_deg"] = s.between_line_step_deg;
  if (!s.bounds.empty())
    json["bounds"] = {{"min", {s.bounds.min.x, s.bounds.min.y, s.bounds.min.z}},
                      {"max", {s.bounds.max.x, s.bounds.max.y, s.bounds.max.z}}};
  json["pose_source"] = s.pose_source;
  if (!s.pose_detail.empty()) json["pose_detail"] = s.pose_detail;
  if (s.sensor_pose)
    json["sensor_pose"] = {{"position", s.sensor_pose->position},
                           {"rotation", s.sensor_pose->rotation}};
  if (!s.caution.empty()) json["caution"] = s.caution;
  return json.dump(2);
}

}  // namespace clearway
