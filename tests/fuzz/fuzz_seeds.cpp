// Writes the seed corpus of every harness into FOLDER/<harness>/: small simulated scans in every
// format and encoding (whole and cut short), LMS200 telegrams, turntable lines, parameter and scene
// JSON. scripts/fuzz adds the heads of the real scans. Usage: fuzz_seeds FOLDER

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "clearway/hardware/lms200_protocol.h"
#include "clearway/io/scan_io.h"
#include "clearway/segmentation/params.h"
#include "clearway/sim/builtin_scenes.h"
#include "clearway/sim/rosi_simulator.h"
#include "clearway/sim/scene_io.h"

namespace fs = std::filesystem;

namespace {

// Bytes of a file cut to this length are a second seed: the readers meet truncated files.
constexpr std::size_t kHeadBytes = 2048;

void put(const fs::path& folder, const std::string& name, const std::string& bytes) {
  fs::create_directories(folder);
  std::ofstream(folder / name, std::ios::binary) << bytes;
}

std::string readAll(const fs::path& file) {
  std::ifstream stream(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>()};
}

void putWithHead(const fs::path& folder, const std::string& name, const std::string& bytes) {
  put(folder, name, bytes);
  if (bytes.size() > kHeadBytes) put(folder, "head-" + name, bytes.substr(0, kHeadBytes));
}

// A scan as fuzz_pipeline reads it (tests/fuzz/pipeline_fuzzer.cpp): flags, line count, an
// optional pose with no turn at `height` decimetres, then the points in millimetres.
std::string encodePipelineInput(const clearway::Scan& scan, std::uint8_t flags, int height) {
  std::string bytes = {char(flags), char(std::min<std::size_t>(scan.lines.size(), 64))};
  if (flags & 2) bytes += std::string{0, 0, 0, 0, 0, char(height)};
  auto put16 = [&bytes](double value) {
    const auto v = std::uint16_t(std::int16_t(std::clamp(value, -32767.0, 32767.0)));
    bytes += char(v & 0xFF);
    bytes += char(v >> 8);
  };
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const clearway::Point3f& p = scan.points[i];
    if (!scan.isValid(i)) {
      for (int k = 0; k < 3; ++k)
        put16(-32768.0);
      continue;
    }
    put16(p.x * 1000.0);
    put16(p.y * 1000.0);
    put16(p.z * 1000.0);
  }
  return bytes;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: fuzz_seeds FOLDER\n");
    return 2;
  }
  const fs::path root = argv[1];
  using namespace clearway;

  sim::SensorModel sensor;
  sensor.lines = 6;  // a few hundred points: small seeds run fast
  const auto scene = *sim::builtinScene("garage");
  const Scan scan = sim::simulateRosi(scene, sensor, sim::defaultPlacement(scene)).scan;

  const fs::path scratch = root / "scratch.pcd";
  fs::create_directories(root);
  const std::pair<PcdEncoding, const char*> encodings[] = {
      {PcdEncoding::kAscii, "ascii"},
      {PcdEncoding::kBinary, "binary"},
      {PcdEncoding::kBinaryCompressed, "binary_compressed"}};
  for (const auto& [encoding, name] : encodings) {
    saveRosiPcd(scan, scratch, encoding);
    const std::string bytes = readAll(scratch);
    putWithHead(root / "fuzz_pcd_reader", std::string(name) + ".pcd", bytes);
    putWithHead(root / "fuzz_pcd_header", std::string(name) + ".pcd", bytes);
  }
  fs::remove(scratch);

  std::string xyz, uos, ply_body, kitti;
  std::size_t valid = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!scan.isValid(i)) continue;
    const Point3f& p = scan.points[i];
    char line[128];
    std::snprintf(line, sizeof line, "%.4f %.4f %.4f %.1f\n", p.x, p.y, p.z, 100.0 + i % 50);
    xyz += line;
    std::snprintf(line, sizeof line, "%.2f %.2f %.2f\n", -p.y * 100, p.z * 100, p.x * 100);
    uos += line;
    std::snprintf(line, sizeof line, "%.4f %.4f %.4f\n", p.x, p.y, p.z);
    ply_body += line;
    const float record[4] = {p.x, p.y, p.z, 0.5F};
    kitti.append(reinterpret_cast<const char*>(record), sizeof record);
    ++valid;
  }
  putWithHead(root / "fuzz_text_reader", "garage.xyz", "# x y z intensity\n" + xyz);
  putWithHead(root / "fuzz_uos_reader", "garage.3d", uos);
  putWithHead(root / "fuzz_kitti_reader", "garage.bin", kitti);
  const std::string ply_header = "ply\nformat ascii 1.0\ncomment seed\nelement vertex " +
                                 std::to_string(valid) +
                                 "\nproperty float x\nproperty float y\nproperty float z\n"
                                 "element face 0\nproperty list uchar int vertex_indices\n"
                                 "end_header\n";
  putWithHead(root / "fuzz_ply_reader", "garage-ascii.ply", ply_header + ply_body);
  std::string binary_ply = "ply\nformat binary_little_endian 1.0\nelement vertex " +
                           std::to_string(valid) +
                           "\nproperty float x\nproperty float y\nproperty float z\n"
                           "property float intensity\nend_header\n";
  binary_ply += kitti;
  putWithHead(root / "fuzz_ply_reader", "garage-binary.ply", binary_ply);

  // The pipeline: the garage and the stairwell as scanned, with turntable angles, on a pose,
  // re-run for another robot.
  const fs::path pipeline = root / "fuzz_pipeline";
  put(pipeline, "garage.bin", encodePipelineInput(scan, 0, 0));
  put(pipeline, "garage-beta-rerun-two-threads.bin", encodePipelineInput(scan, 1 | 4 | 8, 0));
  const auto stairwell = *sim::builtinScene("stairwell");
  const Scan stairs = sim::simulateRosi(stairwell, sensor, sim::defaultPlacement(stairwell)).scan;
  put(pipeline, "stairwell-pose.bin", encodePipelineInput(stairs, 2, 0));

  put(root / "fuzz_params_json", "defaults.json", toJson(SegmentationParams{}).dump(2));
  for (const std::string& name : sim::builtinSceneNames())
    put(root / "fuzz_scene_json", name + ".json",
        sim::sceneToJson(*sim::builtinScene(name)).dump());

  namespace lms = hardware::lms200;
  lms::Bytes values = {std::uint8_t(181 & 0xFF), std::uint8_t(181 >> 8)};
  for (int k = 0; k < 181; ++k) {
    const int raw = k % 17 == 0 ? 0x1FFF : 200 + 3 * k;  // some "no echo" codes
    values.push_back(std::uint8_t(raw & 0xFF));
    values.push_back(std::uint8_t(raw >> 8));
  }
  values.push_back(0x10);
  std::string stream;
  for (const lms::Bytes& telegram :
       {lms::encode(lms::kMeasuredValuesReply, values, 0x80), lms::requestStatus(),
        lms::changeOperatingMode(0x24), lms::switchVariant(180, 50)})
    stream.append(telegram.begin(), telegram.end());
  put(root / "fuzz_lms200_telegrams", "telegrams.bin", "\x06" + stream);

  put(root / "fuzz_turntable_lines", "replies.txt",
      "OK HOME\nOK SPEED\nOK START\nANGLE 1000 0\nANGLE 27000 1013\nANGLE 53000 359990\r\n"
      "STATUS turning 12000 10.5\nERR motor stalled\nOK STOP\nSTATUS idle 0 0\n");
  return 0;
}
