// clearway-cli simulate / scene / eval as a user runs them.

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <thread>

#include "test_support.h"

namespace clearway {
namespace {

using test::runCli;
using test::shellQuote;

TEST(CliSimulate, WritesAnOrganisedRosiScanAndItsTruth) {
  test::TemporaryDirectory directory;
  const auto scan = (directory / "garage.pcd").string();
  const auto result = runCli("simulate garage --lines 80 --door-width 1.1 -o " + shellQuote(scan));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const auto info = runCli("info --json " + shellQuote(scan));
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const auto json = nlohmann::json::parse(info.out);
  EXPECT_EQ(json.at("scan_lines"), 80);
  EXPECT_EQ(json.at("points_per_line"), 180);
  EXPECT_EQ(json.at("points"), 80 * 180);
  EXPECT_EQ(json.at("organised"), true);
  EXPECT_EQ(json.at("has_beta"), true);
  const auto truth = nlohmann::json::parse(test::readBytes(directory / "garage.truth.json"));
  EXPECT_EQ(truth.at("classes").size(), 80u * 180u);
  // The door width parameter reached the scene and its analytic answer.
  EXPECT_DOUBLE_EQ(truth.at("scene").at("passages").at(0).at("width").get<double>(), 1.1);
  EXPECT_EQ(truth.at("reachable").at("lmf_arm_out").at("pairs").size(), 1u);
}

// --dropout loses that share of the returns, and the truth file says so (eval reads the same
// scan the console would).
TEST(CliSimulate, DropoutLosesReturnsAndTheTruthSaysSo) {
  test::TemporaryDirectory directory;
  auto returns = [&](const std::string& options) {
    const auto scan = (directory / "g.pcd").string();
    const auto result = runCli("simulate garage --lines 80 " + options + " -o " + shellQuote(scan));
    EXPECT_EQ(result.exit_code, 0) << result.err;
    const auto info = nlohmann::json::parse(runCli("info --json " + shellQuote(scan)).out);
    return info.at("valid_points").get<double>();
  };
  const double whole = returns("");
  const double lossy = returns("--dropout 0.25");
  EXPECT_NEAR(lossy / whole, 0.75, 0.02);
  const auto truth = nlohmann::json::parse(test::readBytes(directory / "g.truth.json"));
  EXPECT_DOUBLE_EQ(truth.at("sensor").at("dropout").get<double>(), 0.25);
  const auto out = " -o " + shellQuote((directory / "x.pcd").string());
  EXPECT_EQ(runCli("simulate garage --dropout 1" + out).exit_code, 2);
  EXPECT_EQ(runCli("simulate garage --dropout -0.1" + out).exit_code, 2);
}

TEST(CliSimulate, SpeedSetsTheLineCountAndScenesLoadFromFiles) {
  test::TemporaryDirectory directory;
  ASSERT_EQ(runCli("scene stairwell -o " + shellQuote((directory / "s.json").string())).exit_code,
            0);
  const auto scan = (directory / "s.pcd").string();
  const auto result =
      runCli("simulate " + shellQuote((directory / "s.json").string()) +
             " --speed 168.75 --axis down --position 0,0,1.5 -o " + shellQuote(scan));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const auto json = nlohmann::json::parse(runCli("info --json " + shellQuote(scan)).out);
  EXPECT_EQ(json.at("scan_lines"), 80);
}

TEST(CliSimulate, BadScenesAndOptionsFailClearly) {
  test::TemporaryDirectory directory;
  const auto out = " -o " + shellQuote((directory / "x.pcd").string());
  EXPECT_EQ(runCli("simulate volcano" + out).exit_code, 2);
  EXPECT_EQ(runCli("simulate garage --lines 0" + out).exit_code, 2);
  EXPECT_EQ(runCli("simulate garage --axis 0,0,0" + out).exit_code, 2);
  EXPECT_EQ(runCli("simulate garage").exit_code, 2);
  const auto in_wall = runCli("simulate stairwell --position 1,0.8,1" + out);
  EXPECT_EQ(in_wall.exit_code, 2);
  EXPECT_NE(in_wall.err.find("is inside 'left_wall'"), std::string::npos) << in_wall.err;
  // A scene option the scene does not use would be ignored without a word.
  const auto ignored = runCli("simulate doorways --door-width 1.1" + out);
  EXPECT_EQ(ignored.exit_code, 2);
  EXPECT_NE(ignored.err.find("--door-width shapes only the built-in garage scene"),
            std::string::npos)
      << ignored.err;
  EXPECT_EQ(runCli("simulate garage --ramp-slope 20" + out).exit_code, 2);
  test::writeBytes(directory / "broken.json", "{\"primitives\": [{\"class\": \"lava\"}]}");
  const auto broken = runCli("simulate " + shellQuote((directory / "broken.json").string()) + out);
  EXPECT_EQ(broken.exit_code, 1);
  EXPECT_NE(broken.err.find("broken.json"), std::string::npos) << broken.err;
  EXPECT_FALSE(std::filesystem::exists(directory / "x.pcd"));
}

TEST(CliScene, ListsEveryBuiltIn) {
  const auto result = runCli("scene --list");
  ASSERT_EQ(result.exit_code, 0);
  for (const char* name :
       {"garage", "hallway", "outdoor", "stairwell", "doorways", "glass", "no-ground"})
    EXPECT_NE(result.out.find(name), std::string::npos) << name;
}

TEST(CliEval, RefusesAFolderThatIsNoResult) {
  test::TemporaryDirectory directory;
  const auto scan = (directory / "g.pcd").string();
  ASSERT_EQ(runCli("simulate garage --lines 40 -o " + shellQuote(scan)).exit_code, 0);
  const auto result = runCli("eval " + shellQuote((directory / "g.truth.json").string()) + " " +
                             shellQuote(directory.path().string()));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("report.json"), std::string::npos) << result.err;
  EXPECT_EQ(runCli("eval only-one-argument").exit_code, 2);
}

TEST(CliEmulate, WritesThePortsFileAndServesBothTerminals) {
  test::TemporaryDirectory directory;
  const auto ports = (directory / "ports.json").string();
  // In the background for a second; the ports file appears once both terminals are open.
  ASSERT_EQ(
      std::system((shellQuote(CLEARWAY_CLI) + " emulate --scene garage --seconds 1.5 --ports " +
                   shellQuote(ports) + " > /dev/null &")
                      .c_str()),
      0);
  for (int attempt = 0; attempt < 100 && !std::filesystem::exists(ports); ++attempt)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_TRUE(std::filesystem::exists(ports));
  const auto json = nlohmann::json::parse(test::readBytes(ports));
  EXPECT_TRUE(std::filesystem::exists(json.at("lms").get<std::string>()));
  EXPECT_TRUE(std::filesystem::exists(json.at("turntable").get<std::string>()));
  EXPECT_NE(json.at("lms"), json.at("turntable"));
  EXPECT_EQ(runCli("emulate --scene volcano --seconds 0.1").exit_code, 2);
  std::this_thread::sleep_for(
      std::chrono::milliseconds(1600));  // let it end before the folder goes
}

TEST(CliAcquire, AcquiresFromTheEmulatorAndFailsClearlyWithoutADevice) {
  test::TemporaryDirectory directory;
  const auto ports = (directory / "ports.json").string();
  // Long enough for clearway-cli to start and acquire on a busy machine.
  constexpr double kEmulatorSeconds = 6.0;
  const auto emulator_end = std::chrono::steady_clock::now() +
                            std::chrono::milliseconds(int(kEmulatorSeconds * 1000) + 200);
  ASSERT_EQ(
      std::system((shellQuote(CLEARWAY_CLI) + " emulate --scene garage --speed 20 --seconds " +
                   std::to_string(kEmulatorSeconds) + " --ports " + shellQuote(ports) +
                   " > /dev/null &")
                      .c_str()),
      0);
  for (int attempt = 0; attempt < 100 && !std::filesystem::exists(ports); ++attempt)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const auto json = nlohmann::json::parse(test::readBytes(ports));
  const auto scan = (directory / "acquired.pcd").string();
  const auto result = runCli("acquire --lms " + shellQuote(json.at("lms").get<std::string>()) +
                             " --turntable " + shellQuote(json.at("turntable").get<std::string>()) +
                             " --lines 60 -o " + shellQuote(scan));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const auto info = nlohmann::json::parse(runCli("info --json " + shellQuote(scan)).out);
  EXPECT_EQ(info.at("scan_lines"), 60);
  EXPECT_EQ(info.at("points_per_line"), 180);

  const auto missing =
      runCli("acquire --lms /dev/clearway-none --turntable /dev/clearway-none-2 -o " +
             shellQuote((directory / "x.pcd").string()));
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("cannot open /dev/clearway-none"), std::string::npos) << missing.err;
  EXPECT_EQ(runCli("acquire -o x.pcd").exit_code, 2);
  std::this_thread::sleep_until(emulator_end);  // let the emulator end first
}

}  // namespace
}  // namespace clearway
