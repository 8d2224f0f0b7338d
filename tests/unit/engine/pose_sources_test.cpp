// Every pose source and their precedence: the command line over the sidecar over the file, and
// a scan without any pose estimated (or refused with --up none).

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "clearway/io/scan_error.h"
#include "clearway/io/scan_io.h"
#include "clearway/pipeline.h"
#include "clearway/pose.h"
#include "clearway/sim/builtin_scenes.h"
#include "clearway/sim/rosi_simulator.h"
#include "test_support.h"

namespace clearway {
namespace {

sim::SimulatedScan tiltedGarage() {
  const sim::Scene scene = *sim::builtinScene("garage");
  sim::SensorModel sensor;
  sensor.lines = 200;
  sim::ScannerPlacement placement = sim::defaultPlacement(scene);
  placement.axis = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitX()) * placement.axis;
  placement.axis_roll_deg = 60.0;
  return sim::simulateRosi(scene, sensor, placement);
}

// The scan as an acquisition without a pose writes it: VIEWPOINT 0 0 0 1 0 0 0.
std::filesystem::path saveWithoutPose(Scan scan, const std::filesystem::path& file) {
  scan.sensor_pose.reset();
  saveRosiPcd(scan, file);
  return file;
}

Eigen::Vector3d upOf(const SensorPose& pose) {
  return Eigen::Vector3d(pose.rotation[6], pose.rotation[7], pose.rotation[8]);
}

TEST(PoseSources, TheFilesOwnPoseIsUsedWhenNothingElseIsGiven) {
  test::TemporaryDirectory folder;
  const sim::SimulatedScan simulated = tiltedGarage();
  saveRosiPcd(simulated.scan, folder / "garage.pcd");
  Scan scan = loadScan(folder / "garage.pcd");
  EXPECT_EQ(scan.pose_source, PoseSource::kFile);
  const PoseResolution resolution = resolveScanPose(scan, {});
  EXPECT_EQ(resolution.source, PoseSource::kFile);
  EXPECT_LT((upOf(*scan.sensor_pose) - upOf(*simulated.scan.sensor_pose)).norm(), 1e-5);
}

TEST(PoseSources, TheSidecarWinsOverTheFileAndTheCommandLineOverBoth) {
  test::TemporaryDirectory folder;
  const sim::SimulatedScan simulated = tiltedGarage();
  saveRosiPcd(simulated.scan, folder / "garage.pcd");
  const SensorPose sidecar_pose = poseFromUp(Eigen::Vector3d(0.0, 1.0, 0.0));
  writePoseSidecar(sidecar_pose, "arm", folder / "garage.pose.json");

  Scan scan = loadScan(folder / "garage.pcd");
  PoseResolution resolution = resolveScanPose(scan, {});
  EXPECT_EQ(resolution.source, PoseSource::kSidecar);
  EXPECT_LT((upOf(*scan.sensor_pose) - Eigen::Vector3d::UnitY()).norm(), 1e-9);

  PoseRequest up_request;
  up_request.up = Eigen::Vector3d(1.0, 0.0, 0.0);
  resolution = resolveScanPose(scan, up_request);
  EXPECT_EQ(resolution.source, PoseSource::kCommandLine);
  EXPECT_LT((upOf(*scan.sensor_pose) - Eigen::Vector3d::UnitX()).norm(), 1e-9);

  PoseRequest pose_request;
  pose_request.pose = parsePoseText("1,2,3,1,0,0,0");
  resolution = resolveScanPose(scan, pose_request);
  EXPECT_EQ(resolution.source, PoseSource::kCommandLine);
  EXPECT_DOUBLE_EQ(scan.sensor_pose->position[2], 3.0);

  PoseRequest no_sidecar;
  no_sidecar.use_sidecar = false;
  Scan again = loadScan(folder / "garage.pcd");
  EXPECT_EQ(resolveScanPose(again, no_sidecar).source, PoseSource::kFile);
}

TEST(PoseSources, AnUnreadableSidecarIsAnErrorNamingIt) {
  test::TemporaryDirectory folder;
  saveRosiPcd(tiltedGarage().scan, folder / "garage.pcd");
  test::writeBytes(folder / "garage.pose.json", "{\"world_from_scanner\": {\"translation\": [0]}}");
  Scan scan = loadScan(folder / "garage.pcd");
  try {
    resolveScanPose(scan, {});
    FAIL() << "a broken sidecar was accepted";
  } catch (const ScanError& error) {
    EXPECT_NE(std::string(error.what()).find("garage.pose.json"), std::string::npos);
  }
}

// A sidecar is read only as the version it says it is, with each key once, and only when the scan
// has one: a version 99, a repeated key (the last one won, a 180 deg turn) and two sidecars (one
// was read, the other ignored) were all taken silently.
TEST(PoseSources, ASidecarThatIsNotPlainlyOneIsRefusedNamingWhy) {
  test::TemporaryDirectory folder;
  saveRosiPcd(tiltedGarage().scan, folder / "garage.pcd");
  const std::string pose = R"("world_from_scanner": {"translation": [0, 0, 1], "rotation_wxyz": )";
  const std::pair<std::string, std::string> cases[] = {
      {R"({"version": 99, )" + pose + "[1, 0, 0, 0]}}",
       "version 99: this Clearway reads version 1"},
      {"{" + pose + "[1, 0, 0, 0]}}", "version missing"},
      {R"({"version": 1, )" + pose + R"([1, 0, 0, 0], "rotation_wxyz": [0, 1, 0, 0]}})",
       "the key \"rotation_wxyz\" is given twice"},
      {R"({"version": 1, )" + pose + R"([1, "0", 0, 0]}})", "\"rotation_wxyz\" holds \"0\""},
      {R"({"version": 1, "source": 12, )" + pose + "[1, 0, 0, 0]}}", "\"source\" must be text"}};
  for (const auto& [text, why] : cases) {
    test::writeBytes(folder / "garage.pose.json", text);
    Scan scan = loadScan(folder / "garage.pcd");
    try {
      resolveScanPose(scan, {});
      ADD_FAILURE() << "accepted: " << text;
    } catch (const ScanError& error) {
      EXPECT_NE(std::string(error.what()).find(why), std::string::npos) << error.what();
    }
  }
  test::writeBytes(folder / "garage.pose.json", R"({"version": 1, )" + pose + "[1, 0, 0, 0]}}");
  Scan one = loadScan(folder / "garage.pcd");
  EXPECT_EQ(resolveScanPose(one, {}).source, PoseSource::kSidecar);
  test::writeBytes(folder / "garage.pcd.pose.json", R"({"version": 1, )" + pose + "[0, 1, 0, 0]}}");
  Scan two = loadScan(folder / "garage.pcd");
  try {
    resolveScanPose(two, {});
    ADD_FAILURE() << "two sidecars, one taken";
  } catch (const ScanError& error) {
    EXPECT_NE(std::string(error.what()).find("two pose sidecars"), std::string::npos)
        << error.what();
  }
}

TEST(PoseSources, MalformedPoseTextIsRefusedReadably) {
  EXPECT_THROW(parsePoseText("1,2,3"), std::invalid_argument);
  EXPECT_THROW(parsePoseText("0,0,0,0,0,0,0"), std::invalid_argument);
  EXPECT_THROW(parsePoseText("0,0,nan,1,0,0,0"), std::invalid_argument);
  EXPECT_THROW(parseUpText("0,0,0"), std::invalid_argument);
  EXPECT_NEAR(parseUpText("0,0,2").z(), 1.0, 1e-12);
}

TEST(PoseSources, AnAcquisitionWithASidecarFindsTheGroundItLosesWithoutOne) {
  test::TemporaryDirectory folder;
  const sim::SimulatedScan simulated = tiltedGarage();
  const auto file = saveWithoutPose(simulated.scan, folder / "acquired.pcd");
  // Without a pose and without estimating, no ground, and the reason says why.
  Scan bare = loadScan(file);
  EXPECT_EQ(resolveScanPose(bare, {}).source, PoseSource::kNone);
  SegmentationParams refuse;
  refuse.ground.estimate_up = 0;
  const PipelineResult refused = runPipeline(bare, refuse);
  EXPECT_FALSE(refused.trusted());
  EXPECT_NE(refused.reason.find("no pose"), std::string::npos);
  EXPECT_EQ(refused.map.counts[std::size_t(CellLabel::kTraversable)], 0U);

  writePoseSidecar(*simulated.scan.sensor_pose, "arm", folder / "acquired.pose.json");
  Scan posed = loadScan(file);
  EXPECT_EQ(resolveScanPose(posed, {}).source, PoseSource::kSidecar);
  const PipelineResult result = runPipeline(posed, SegmentationParams{});
  ASSERT_TRUE(result.trusted()) << result.reason;
  EXPECT_EQ(result.analysis->pose_source, PoseSource::kSidecar);
  const Plane& floor =
      result.analysis->planes.planes[std::size_t(result.analysis->reference_ground)];
  EXPECT_GT(std::abs(floor.normal.dot(upOf(*simulated.scan.sensor_pose))), std::cos(0.05));
}

TEST(PoseSources, TheCommandLineSaysWhereThePoseCameFrom) {
  test::TemporaryDirectory folder;
  const sim::SimulatedScan simulated = tiltedGarage();
  const auto file = saveWithoutPose(simulated.scan, folder / "acquired.pcd");
  const Eigen::Vector3d up = upOf(*simulated.scan.sensor_pose);
  const std::string up_text =
      std::to_string(up.x()) + "," + std::to_string(up.y()) + "," + std::to_string(up.z());

  auto info = test::runCli("info --json " + test::shellQuote(file.string()));
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_EQ(nlohmann::json::parse(info.out).at("pose_source"), "none");
  info = test::runCli("info --json --up " + up_text + " " + test::shellQuote(file.string()));
  EXPECT_EQ(nlohmann::json::parse(info.out).at("pose_source"), "command line");

  const auto out = folder / "result";
  const auto segment = test::runCli("segment " + test::shellQuote(file.string()) + " --up " +
                                    up_text + " -o " + test::shellQuote(out.string()));
  ASSERT_EQ(segment.exit_code, 0) << segment.err;
  const auto report = nlohmann::json::parse(test::readBytes(out / "report.json"));
  EXPECT_TRUE(report.at("ground_found").get<bool>());
  EXPECT_EQ(report.at("pose").at("source"), "command line");
  // An up direction places the floor, not the robot: its heading is a guess.
  EXPECT_EQ(report.at("robot_pose").at("heading"), "guessed");

  const auto none = test::runCli("segment " + test::shellQuote(file.string()) + " --up none -o " +
                                 test::shellQuote((folder / "none").string()));
  ASSERT_EQ(none.exit_code, 0) << none.err;
  const auto refused = nlohmann::json::parse(test::readBytes(folder / "none" / "report.json"));
  EXPECT_FALSE(refused.at("ground_found").get<bool>());
  EXPECT_NE(refused.at("reason").get<std::string>().find("no pose"), std::string::npos);
  // Nothing was given or estimated: no up direction, and no confidence in one.
  EXPECT_EQ(refused.at("pose").at("source"), "none");
  EXPECT_TRUE(refused.at("pose").at("up_in_scanner_frame").is_null());
  EXPECT_EQ(refused.at("pose").at("confidence").get<double>(), 0.0);

  const auto bad = test::runCli("segment " + test::shellQuote(file.string()) + " --pose 1,2 -o " +
                                test::shellQuote(out.string()));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--pose"), std::string::npos);
}

}  // namespace
}  // namespace clearway
