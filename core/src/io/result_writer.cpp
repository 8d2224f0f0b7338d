#include "clearway/io/result_writer.h"

#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "clearway/io/file_util.h"
#include "clearway/io/result_manifest.h"
#include "clearway/io/scan_error.h"
#include "clearway/pose.h"

namespace clearway {
namespace {

// An up direction only estimated from the scan: the console draws nothing traversable until the
// operator confirms it, and traversability.png, a picture for people, does the same. The data
// files (labels, ROS map) keep the engine's answer; report.json says on what it rests.
bool traversableWithheldInPicture(const PipelineResult& result) {
  return result.trusted() && result.analysis->pose_source == PoseSource::kEstimated;
}

// Image row 0 is the map's top (largest y), as image viewers and ROS expect.
std::vector<std::uint8_t> topDown(const std::vector<std::uint8_t>& layer, const MapGrid& grid,
                                  std::uint8_t (*pixel)(std::uint8_t) = nullptr) {
  std::vector<std::uint8_t> image(grid.cells());
  for (int row = 0; row < grid.height; ++row)
    for (int column = 0; column < grid.width; ++column) {
      const std::uint8_t value = layer[grid.index(column, row)];
      image[std::size_t(grid.height - 1 - row) * std::size_t(grid.width) + std::size_t(column)] =
          pixel ? pixel(value) : value;
    }
  return image;
}

void writePgm(const std::filesystem::path& file, int width, int height,
              const std::vector<std::uint8_t>& pixels) {
  std::string bytes = "P5\n" + std::to_string(width) + " " + std::to_string(height) + "\n255\n";
  bytes.append(pixels.begin(), pixels.end());
  writeTextFileAtomically(file, bytes);
}

// ROS occupancy: 254 free, 0 occupied, 205 unknown.
std::uint8_t occupancy(std::uint8_t label) {
  switch (CellLabel(label)) {
    case CellLabel::kTraversable:
    case CellLabel::kCareful:
      return 254;
    case CellLabel::kUnknown:
      return 205;
    default:
      return 0;
  }
}

}  // namespace

std::string reportJson(const PipelineResult& result, const SegmentationParams& params,
                       const std::string& scan_name) {
  const ScanAnalysis& analysis = *result.analysis;
  nlohmann::ordered_json report;
  report["scan"] = utf8FileName(scan_name);  // JSON needs UTF-8; lossless for any bytes
  report["ground_found"] = analysis.ground_found;
  if (!result.reason.empty()) report["reason"] = result.reason;
  report["robot"] = {
      {"name", result.robot.name},         {"width", result.robot.width},
      {"length", result.robot.length},     {"height", result.robot.height},
      {"max_step", result.robot.max_step}, {"max_slope_deg", params.ground.max_slope_deg}};
  report["points"] = analysis.scan_points;
  report["valid_points"] = analysis.valid_points;
  report["segments"] = analysis.segments.size();
  report["candidate_planes"] = analysis.candidate_planes;
  report["rejected_planes"] = analysis.planes.rejected;
  auto planes = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < analysis.planes.planes.size(); ++k) {
    const Plane& plane = analysis.planes.planes[k];
    const bool accepted =
        std::find(result.map.accepted_ground.begin(), result.map.accepted_ground.end(), int(k)) !=
        result.map.accepted_ground.end();
    planes.push_back({{"normal", {plane.normal.x(), plane.normal.y(), plane.normal.z()}},
                      {"offset", plane.offset},
                      {"points", plane.support_points},
                      {"area", plane.support_area},
                      {"segments", plane.segments.size()},
                      {"rms", plane.rms},
                      {"inner_fraction", plane.inner_fraction},
                      {"kind", planeKindName(plane.kind)},
                      {"reference_ground", int(k) == analysis.reference_ground},
                      {"reachable_ground", accepted},
                      {"validated", plane.validated}});
  }
  report["planes"] = planes;
  const Eigen::Vector3d& up = analysis.up;
  // Without a pose and without an estimate there is no up direction to report.
  const bool has_up = analysis.pose_source != PoseSource::kNone;
  report["pose"] = {{"source", poseSourceName(analysis.pose_source)},
                    {"up_in_scanner_frame", has_up ? nlohmann::ordered_json{up.x(), up.y(), up.z()}
                                                   : nlohmann::ordered_json()},
                    {"confidence", analysis.up_confidence},
                    {"picture_withholds_traversable", traversableWithheldInPicture(result)}};
  const TraversabilityMap& map = result.map;
  // "guessed": no recorded robot frame; the reach starts from every orientation the box fits in
  // at the robot's place.
  report["robot_pose"] = {{"x", map.robot_pose.x},
                          {"y", map.robot_pose.y},
                          {"yaw_deg", map.robot_pose.yaw * 180.0 / std::numbers::pi},
                          {"heading", map.robot_heading_known ? "recorded" : "guessed"}};
  report["reach"] = {{"file", "reach.pgm"},
                     {"reachable_cells", map.reachable_cells},
                     {"fits_not_reachable_cells", map.fits_not_reachable_cells}};
  if (!map.reach_limit.empty()) report["reach"]["limit"] = map.reach_limit;
  if (result.goal) {
    nlohmann::ordered_json path = nlohmann::ordered_json::array();
    for (const PathPose& pose : result.goal->path)
      path.push_back({pose.x, pose.y, pose.heading_deg});
    nlohmann::ordered_json goal = {{"reachable", result.goal->reachable}};
    if (!result.goal->reason.empty()) goal["reason"] = result.goal->reason;
    goal["path"] = path;
    goal["length_m"] = result.goal->length_m;
    goal["unvouched_m"] = result.goal->unvouched_m;
    report["goal"] = goal;
  }
  nlohmann::ordered_json cells;
  for (int label = 0; label < kCellLabelCount; ++label)
    cells[std::string(labelName(CellLabel(label)))] = result.map.counts[std::size_t(label)];
  report["cells"] = cells;
  // Staircases in the map frame; index k is the value of ScanAnalysis::stairs.cell_staircase.
  auto stairs = nlohmann::ordered_json::array();
  for (const Staircase& flight : analysis.stairs.staircases) {
    const std::string why = stairVerdict(flight, result.robot);
    const Eigen::Vector2d foot =
        flight.start() * flight.up + (flight.across_min + flight.across_max) / 2 * flight.across;
    nlohmann::ordered_json entry = {{"steps", flight.steps()},
                                    {"rise", flight.rise},
                                    {"tread", flight.tread},
                                    {"direction_deg", flight.yawDegrees()},
                                    {"slope_deg", flight.slopeDegrees()},
                                    {"width", flight.width()},
                                    {"foot", {foot.x(), foot.y()}},
                                    {"bottom_z", flight.bottom()},
                                    {"top_z", flight.top()},
                                    {"climbable", why.empty()}};
    if (!why.empty()) entry["reason"] = why;
    stairs.push_back(entry);
  }
  report["stairs"] = stairs;
  nlohmann::ordered_json timing;
  for (const StageTiming& stage : result.timings)
    timing[stage.stage] = stage.milliseconds;
  timing["total"] = result.total_ms;
  report["timing_ms"] = timing;
  const Eigen::Matrix4d m = analysis.map_from_scanner.matrix();
  std::vector<double> row_major;
  for (int i = 0; i < 16; ++i)
    row_major.push_back(m(i / 4, i % 4));
  const MapGrid& grid = result.map.grid;
  report["map"] = {
      {"resolution", grid.resolution},
      {"origin", {grid.origin.x(), grid.origin.y()}},
      {"width", grid.width},
      {"height", grid.height},
      {"labels", "labels.pgm"},
      {"label_values", {"unknown", "traversable", "careful", "obstacle", "impassable", "stairs"}},
      {"map_from_scanner", row_major}};
  report["point_classes"] = "point_classes.u8";
  report["scene"] = {{"file", "scene.ply"},
                     {"ground_triangles", result.scene.triangles.size()},
                     {"wall_cuboids", result.scene.walls.size()},
                     {"obstacle_cubes", result.scene.obstacles.size()}};
  report["params"] = toJson(params);
  return report.dump(2) + "\n";
}

void writeLabelsPgm(const TraversabilityMap& map, const std::filesystem::path& file) {
  writePgm(file, map.grid.width, map.grid.height, topDown(map.labels, map.grid));
}

void writeReasonsPgm(const TraversabilityMap& map, const std::filesystem::path& file) {
  writePgm(file, map.grid.width, map.grid.height, topDown(map.reasons, map.grid));
}

void writeReachPgm(const TraversabilityMap& map, const std::filesystem::path& file) {
  std::vector<std::uint8_t> reach = map.reach;
  reach.resize(map.grid.cells(), 0);  // no search ran (no ground): nothing is reachable
  writePgm(file, map.grid.width, map.grid.height, topDown(reach, map.grid));
}

void writeRosMap(const TraversabilityMap& map, const std::filesystem::path& pgm_file) {
  writePgm(pgm_file, map.grid.width, map.grid.height, topDown(map.labels, map.grid, occupancy));
  std::ostringstream yaml;
  yaml << "image: " << pgm_file.filename().string() << "\nresolution: " << map.grid.resolution
       << "\norigin: [" << map.grid.origin.x() << ", " << map.grid.origin.y() << ", 0.0]\n"
       << "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
  std::filesystem::path yaml_file = pgm_file;
  yaml_file.replace_extension(".yaml");
  writeTextFileAtomically(yaml_file, yaml.str());
}

void writeTraversabilityPng(const TraversabilityMap& map, const std::filesystem::path& file,
                            bool withhold_drivable) {
  cv::Mat image(std::max(map.grid.height, 1), std::max(map.grid.width, 1), CV_8UC3,
                cv::Scalar(60, 60, 60));
  for (int row = 0; row < map.grid.height; ++row)
    for (int column = 0; column < map.grid.width; ++column) {
      CellLabel label = map.label(column, row);
      if (withhold_drivable && drivable(label)) label = CellLabel::kUnknown;
      const auto rgb = labelColour(label);
      image.at<cv::Vec3b>(map.grid.height - 1 - row, column) = cv::Vec3b(rgb[2], rgb[1], rgb[0]);
    }
  std::vector<std::uint8_t> png;
  if (!cv::imencode(".png", image, png)) throw ScanError(file, "cannot encode the PNG");
  writeTextFileAtomically(file, std::string(png.begin(), png.end()));
}

void writeScenePly(const SceneGeometry& scene, const std::filesystem::path& file) {
  // Streamed through the checked, buffered file: a scene of tens of millions of triangles is never
  // held a second time as bytes (nor a third, in a growing string's copies).
  const std::size_t boxes = scene.walls.size() + scene.obstacles.size();
  const std::size_t vertex_count = scene.vertices.size() + 8 * boxes;
  const std::size_t face_count = scene.triangles.size() + 12 * boxes;
  writeFileAtomically(file, [&](const std::filesystem::path& temporary) {
    CheckedFile out(temporary, file);
    out.write(
        "ply\nformat binary_little_endian 1.0\ncomment Clearway traversability scene (scanner "
        "frame)\nelement vertex " +
        std::to_string(vertex_count) +
        "\nproperty float x\nproperty float y\nproperty float z\n"
        "property uchar red\nproperty uchar green\nproperty uchar blue\n"
        "element face " +
        std::to_string(face_count) + "\nproperty list uchar uint vertex_indices\nend_header\n");
    auto writeVertex = [&out](const Eigen::Vector3f& p, const std::array<std::uint8_t, 3>& c) {
      char bytes[3 * sizeof(float) + 3];
      const float xyz[3] = {p.x(), p.y(), p.z()};
      std::memcpy(bytes, xyz, sizeof xyz);
      std::memcpy(bytes + sizeof xyz, c.data(), 3);
      out.write(std::string_view(bytes, sizeof bytes));
    };
    auto writeFace = [&out](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
      char bytes[1 + 3 * sizeof(std::uint32_t)];
      bytes[0] = char(3);
      const std::uint32_t corners[3] = {a, b, c};
      std::memcpy(bytes + 1, corners, sizeof corners);
      out.write(std::string_view(bytes, sizeof bytes));
    };
    for (std::size_t i = 0; i < scene.vertices.size(); ++i)
      writeVertex(scene.vertices[i], labelColour(scene.vertex_labels[i]));
    // Each box: its 8 corners, then (below) its 12 faces, boxes in the same order.
    auto boxCorners = [&](const SceneBox& box) {
      const auto c = labelColour(box.label);
      for (int corner = 0; corner < 8; ++corner) {
        const Eigen::Vector3f sign((corner & 1) ? 1.F : -1.F, (corner & 2) ? 1.F : -1.F,
                                   (corner & 4) ? 1.F : -1.F);
        writeVertex(box.center + box.axes * sign.cwiseProduct(box.half_size), c);
      }
    };
    for (const SceneBox& box : scene.walls)
      boxCorners(box);
    for (const SceneBox& box : scene.obstacles)
      boxCorners(box);
    for (const auto& t : scene.triangles)
      writeFace(t[0], t[1], t[2]);
    static constexpr std::uint32_t kFaces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6},
                                                    {0, 1, 4}, {1, 5, 4}, {2, 6, 3}, {3, 6, 7},
                                                    {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    auto base = std::uint32_t(scene.vertices.size());
    for (std::size_t box = 0; box < boxes; ++box, base += 8)
      for (const auto& f : kFaces)
        writeFace(base + f[0], base + f[1], base + f[2]);
    out.close();
  });
}

void writeResultFolder(const PipelineResult& result, const SegmentationParams& params,
                       const std::string& scan_name, const std::filesystem::path& folder) {
  std::error_code error;
  if (folder.has_parent_path()) std::filesystem::create_directories(folder.parent_path(), error);
  if (error) throw ScanError(folder, "cannot create the output folder: " + error.message());
  // Written as a unit: everything goes into a new folder beside `folder`, which then replaces it,
  // so a failure (full disk) leaves the old result whole and a reader never sees a mix.
  replaceFolderAtomically(folder, [&](const std::filesystem::path& staging) {
    writeLabelsPgm(result.map, staging / "labels.pgm");
    writeReasonsPgm(result.map, staging / "reasons.pgm");
    writeReachPgm(result.map, staging / "reach.pgm");
    writeRosMap(result.map, staging / "map.pgm");
    writeTraversabilityPng(result.map, staging / "traversability.png",
                           traversableWithheldInPicture(result));
    writeScenePly(result.scene, staging / "scene.ply");
    std::string classes(result.point_classes.size(), '\0');
    for (std::size_t i = 0; i < classes.size(); ++i)
      classes[i] = char(result.point_classes[i]);
    writeTextFileAtomically(staging / "point_classes.u8", classes);
    writeTextFileAtomically(staging / "report.json", reportJson(result, params, scan_name));
    // The manifest last: it ties the files of this run together (eval checks it).
    writeResultManifest(staging,
                        {"labels.pgm", "reasons.pgm", "reach.pgm", "map.pgm", "map.yaml",
                         "traversability.png", "scene.ply", "point_classes.u8", "report.json"});
  });
}

}  // namespace clearway
