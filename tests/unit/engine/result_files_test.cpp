// The segment output folder: every file there, consistent with the report, readable by our own
// readers and by eval.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "clearway/eval/evaluation.h"
#include "clearway/io/result_writer.h"
#include "clearway/io/scan_io.h"
#include "engine_fixtures.h"
#include "test_support.h"

namespace clearway {
namespace {

TEST(ResultFolder, HoldsEveryFileTheIssueNamesConsistently) {
  const auto run = test::simulateAndSegment("garage", 200);
  test::TemporaryDirectory directory;
  const SegmentationParams params;
  writeResultFolder(run.result, params, "garage.pcd", directory.path());
  for (const char* name : {"report.json", "labels.pgm", "reasons.pgm", "map.pgm", "map.yaml",
                           "traversability.png", "scene.ply", "point_classes.u8"})
    EXPECT_TRUE(std::filesystem::exists(directory / name)) << name;

  const auto report = nlohmann::json::parse(test::readBytes(directory / "report.json"));
  EXPECT_EQ(report.at("ground_found"), true);
  EXPECT_EQ(report.at("map").at("map_from_scanner").size(), 16u);
  EXPECT_GT(report.at("timing_ms").at("total").get<double>(), 0.0);
  for (const char* stage :
       {"sensor", "lines", "clustering", "validation", "ground", "traversability", "scene"})
    EXPECT_TRUE(report.at("timing_ms").contains(stage)) << stage;
  const std::string pgm = test::readBytes(directory / "labels.pgm");
  const std::string header = "P5\n" + std::to_string(report.at("map").at("width").get<int>()) +
                             " " + std::to_string(report.at("map").at("height").get<int>()) +
                             "\n255\n";
  ASSERT_EQ(pgm.substr(0, header.size()), header);
  EXPECT_EQ(pgm.size(), header.size() + run.result.map.labels.size());
  EXPECT_EQ(test::readBytes(directory / "point_classes.u8").size(), run.simulated.scan.size());
  EXPECT_NE(test::readBytes(directory / "map.yaml").find("image: map.pgm"), std::string::npos);

  // The scene is a PLY our own reader opens: ground vertices plus 8 corners per box.
  LoadOptions options;
  options.self_hit_radius = 0.0;
  const Scan scene = loadScan(directory / "scene.ply", options);
  EXPECT_EQ(scene.size(),
            run.result.scene.vertices.size() +
                8 * (run.result.scene.walls.size() + run.result.scene.obstacles.size()));

  // And eval reads the folder back.
  const eval::SegmentationResult result = eval::loadSegmentationResult(directory.path());
  EXPECT_EQ(result.map.width, run.result.map.grid.width);
  EXPECT_EQ(result.point_classes.size(), run.simulated.scan.size());
}

TEST(ResultFolder, AnUntrustedResultSaysWhyAndHasNoGreen) {
  const auto run = test::simulateAndSegment("no-ground", 100);
  test::TemporaryDirectory directory;
  writeResultFolder(run.result, {}, "x.pcd", directory.path());
  const auto report = nlohmann::json::parse(test::readBytes(directory / "report.json"));
  EXPECT_EQ(report.at("ground_found"), false);
  EXPECT_NE(report.at("reason").get<std::string>().find("no ground"), std::string::npos);
  EXPECT_EQ(report.at("cells").at("traversable"), 0);
}

TEST(SceneGeometry, GroundTrianglesWallCuboidsAndObstacleCubes) {
  const auto run = test::simulateAndSegment("garage", 300);
  const SceneGeometry& scene = run.result.scene;
  EXPECT_GT(scene.triangles.size(), 1000u);
  EXPECT_GE(scene.walls.size(), 3u);
  EXPECT_GT(scene.obstacles.size(), 10u);
  // The drawn floor is where the robot may drive: at least two corners of every triangle on a
  // cell it fits on.
  for (const auto& triangle : scene.triangles) {
    int on_drivable = 0;
    for (std::uint32_t v : triangle) {
      ASSERT_LT(v, scene.vertices.size());
      on_drivable += robotFits(scene.vertex_labels[v]);
    }
    EXPECT_GE(on_drivable, 2);
  }
}

}  // namespace
}  // namespace clearway
