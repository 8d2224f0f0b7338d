#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "clearway/scene/scene_geometry.h"
#include "test_support.h"

namespace clearway {
namespace {

using test::runCli;
using test::shellQuote;

TEST(CliSegment, WritesTheResultFolderAndEvalScoresIt) {
  test::TemporaryDirectory directory;
  const auto scan = (directory / "g.pcd").string();
  ASSERT_EQ(runCli("simulate garage --lines 200 -o " + shellQuote(scan)).exit_code, 0);
  const auto out = (directory / "out").string();
  const auto result =
      runCli("segment " + shellQuote(scan) + " -o " + shellQuote(out) + " --robot-width 0.85");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("ground found: yes"), std::string::npos);
  const auto report = nlohmann::json::parse(test::readBytes(directory / "out" / "report.json"));
  EXPECT_DOUBLE_EQ(report.at("robot").at("width").get<double>(), 0.85);
  const auto evaluation = runCli(
      "eval --json " + shellQuote((directory / "g.truth.json").string()) + " " + shellQuote(out));
  ASSERT_EQ(evaluation.exit_code, 0) << evaluation.err;
  const auto scores = nlohmann::json::parse(evaluation.out);
  EXPECT_EQ(scores.at("map").at("false_traversable_cells"), 0);
  EXPECT_GT(scores.at("planes").at("recall").get<double>(), 0.8);
}

TEST(CliSegment, AChangedPresetIsReportedAsACustomRobot) {
  test::TemporaryDirectory directory;
  const auto scan = (directory / "g.pcd").string();
  ASSERT_EQ(runCli("simulate garage --lines 20 -o " + shellQuote(scan)).exit_code, 0);
  for (const auto& [options, name] :
       {std::pair{std::string(" --robot-width 0.85"), std::string("LMF smallest")},
        {" --robot-width 0.9 --robot-length 0.5", "custom"}}) {
    const auto out = (directory / "out").string();
    const auto result = runCli("segment " + shellQuote(scan) + " -o " + shellQuote(out) + options);
    ASSERT_EQ(result.exit_code, 0) << result.err;
    const auto report = nlohmann::json::parse(test::readBytes(directory / "out" / "report.json"));
    EXPECT_EQ(report.at("robot").at("name").get<std::string>(), name) << options;
  }
}

// The console withholds green until an estimated up direction is confirmed; the CLI writes the map
// but says on the goal's answer that it rests on the estimate.
TEST(CliSegment, AnAnswerFromAnEstimatedUpDirectionSaysSo) {
  CLEARWAY_REAL_SCAN_OR_SKIP(scan, "octomap-stairs/scan.dat");
  test::TemporaryDirectory directory;
  const auto out = (directory / "out").string();
  const auto estimated =
      runCli("segment " + shellQuote(scan.string()) + " -o " + shellQuote(out) + " --goal 3,0");
  ASSERT_EQ(estimated.exit_code, 0) << estimated.err;
  EXPECT_NE(estimated.out.find("up direction: estimated"), std::string::npos) << estimated.out;
  EXPECT_NE(estimated.out.find("goal: reachable (if the estimated up direction is right)"),
            std::string::npos)
      << estimated.out;
  // The picture, for people, withholds what the console withholds: the map's data keep it.
  const auto report = nlohmann::json::parse(test::readBytes(directory / "out" / "report.json"));
  EXPECT_TRUE(report.at("pose").at("picture_withholds_traversable").get<bool>());
  EXPECT_GT(report.at("cells").at("traversable").get<int>(), 0);
  const std::string png = test::readBytes(directory / "out" / "traversability.png");
  const cv::Mat picture =
      cv::imdecode(std::vector<std::uint8_t>(png.begin(), png.end()), cv::IMREAD_COLOR);
  ASSERT_FALSE(picture.empty());
  int drivable_pixels = 0;
  for (const cv::Vec3b& bgr : cv::Mat_<cv::Vec3b>(picture))
    for (const CellLabel label :
         {CellLabel::kTraversable, CellLabel::kCareful, CellLabel::kObstacle, CellLabel::kStairs}) {
      const auto rgb = labelColour(label);
      drivable_pixels += bgr == cv::Vec3b(rgb[2], rgb[1], rgb[0]);
    }
  EXPECT_EQ(drivable_pixels, 0);
}

TEST(CliBench, TimesEveryStageOfEveryRun) {
  test::TemporaryDirectory directory;
  const auto scan = (directory / "g.pcd").string();
  ASSERT_EQ(runCli("simulate garage --lines 60 -o " + shellQuote(scan)).exit_code, 0);
  const auto result = runCli("bench " + shellQuote(scan) + " --repeat 5 --threads 1 --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const auto figures = nlohmann::json::parse(result.out);
  EXPECT_EQ(figures.at("points"), 60 * 180);
  EXPECT_EQ(figures.at("repeat"), 5);
  EXPECT_EQ(figures.at("threads"), 1);
  EXPECT_TRUE(figures.at("ground_found").get<bool>());
  EXPECT_GE(figures.at("planes").get<int>(), 3);  // floor, walls
  const double median = figures.at("median_ms").get<double>();
  EXPECT_GT(median, 0.0);
  EXPECT_GE(figures.at("p95_ms").get<double>(), median);
  EXPECT_NEAR(figures.at("points_per_s").get<double>(), 60 * 180 / (median / 1000.0), 1.0);
  const auto& stages = figures.at("stages");
  ASSERT_TRUE(stages.contains("traversability")) << stages.dump();
  ASSERT_TRUE(stages.contains("scene")) << stages.dump();
  double stage_sum = 0.0;
  for (const auto& stage : stages)
    stage_sum += stage.at("median_ms").get<double>();
  EXPECT_GT(stage_sum, 0.5 * median);  // the stages account for the run
  // Two scans give one entry each.
  const auto two =
      runCli("bench " + shellQuote(scan) + " " + shellQuote(scan) + " --repeat 1 --json");
  ASSERT_EQ(two.exit_code, 0) << two.err;
  EXPECT_EQ(nlohmann::json::parse(two.out).size(), 2u);
}

TEST(CliBench, PeersRunOnTheSameScanAndAreScoredAgainstTheTruth) {
  test::TemporaryDirectory directory;
  const auto scan = (directory / "g.pcd").string();
  ASSERT_EQ(runCli("simulate garage --lines 80 -o " + shellQuote(scan)).exit_code, 0);
  const auto result = runCli("bench " + shellQuote(scan) + " --repeat 2 --peers --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const auto figures = nlohmann::json::parse(result.out);
  // Our own result is scored too: the truth file lies beside the simulated scan.
  EXPECT_GT(figures.at("accuracy").at("plane_recall").get<double>(), 0.5);
  EXPECT_EQ(figures.at("map_accuracy").at("false_traversable_cells"), 0);
  const auto& peers = figures.at("peers");
  for (const char* name : {"pcl_organized_multiplane", "pcl_region_growing",
                           "pcl_ransac_multiplane", "opencv_dilate_footprints"}) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(peers.contains(name)) << peers.dump();
    const auto& peer = peers.at(name);
    EXPECT_GT(peer.at("median_ms").get<double>(), 0.0);
    EXPECT_GE(peer.at("p95_ms").get<double>(), peer.at("median_ms").get<double>());
    EXPECT_EQ(peer.at("runs"), 2);
  }
  EXPECT_GT(peers.at("pcl_ransac_multiplane").at("planes").get<int>(), 2);
  EXPECT_GT(peers.at("pcl_ransac_multiplane").at("accuracy").at("point_purity").get<double>(), 0.8);
  EXPECT_GT(peers.at("opencv_dilate_footprints").at("traversable_cells").get<int>(), 100);
  EXPECT_TRUE(peers.at("opencv_dilate_footprints").contains("map_accuracy"));
  // Without --peers there are none, and a scan without truth has no accuracy.
  std::filesystem::remove(directory / "g.truth.json");
  const auto plain =
      nlohmann::json::parse(runCli("bench " + shellQuote(scan) + " --repeat 1 --json").out);
  EXPECT_FALSE(plain.contains("peers"));
  EXPECT_FALSE(plain.contains("accuracy"));
}

TEST(CliBench, BadInputsFailClearly) {
  test::TemporaryDirectory directory;
  EXPECT_EQ(runCli("bench").exit_code, 2);
  EXPECT_EQ(runCli("bench x.pcd --repeat 0").exit_code, 2);
  const auto missing = runCli("bench " + shellQuote((directory / "missing.pcd").string()));
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("missing.pcd"), std::string::npos) << missing.err;
  // A truth file that belongs to another scan is refused, naming both files.
  const auto small = (directory / "small.pcd").string(), large = (directory / "large.pcd").string();
  ASSERT_EQ(runCli("simulate garage --lines 40 -o " + shellQuote(small)).exit_code, 0);
  ASSERT_EQ(runCli("simulate garage --lines 60 -o " + shellQuote(large)).exit_code, 0);
  std::filesystem::copy_file(directory / "small.truth.json", directory / "large.truth.json",
                             std::filesystem::copy_options::overwrite_existing);
  const auto foreign = runCli("bench " + shellQuote(large) + " --repeat 1");
  EXPECT_EQ(foreign.exit_code, 1);
  EXPECT_NE(foreign.err.find("not this scan's truth"), std::string::npos) << foreign.err;
  EXPECT_NE(foreign.err.find("large.truth.json"), std::string::npos) << foreign.err;
}

TEST(CliSegment, BadInputsFailClearly) {
  test::TemporaryDirectory directory;
  const auto out = " -o " + shellQuote((directory / "out").string());
  EXPECT_EQ(runCli("segment " + shellQuote((directory / "missing.pcd").string()) + out).exit_code,
            1);
  EXPECT_EQ(runCli("segment x.pcd").exit_code, 2);
  EXPECT_EQ(runCli("segment x.pcd --robot-width -2" + out).exit_code, 2);
  EXPECT_EQ(runCli("segment x.pcd --method magic" + out).exit_code, 2);
  test::writeBytes(directory / "p.json", "{\"map\": {\"resolution\": 9}}");
  const auto bad_params =
      runCli("segment x.pcd --params " + shellQuote((directory / "p.json").string()) + out);
  EXPECT_EQ(bad_params.exit_code, 2);
  EXPECT_NE(bad_params.err.find("map.resolution"), std::string::npos) << bad_params.err;
}

}  // namespace
}  // namespace clearway
