// clearway-cli info as a user runs it: exit codes, the one-line error, and the JSON keys.

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "test_support.h"

namespace clearway {
namespace {

using test::runCli;
using test::shellQuote;

TEST(CliInfo, JsonOnARealScanHasTheAgreedKeys) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, "octomap-stairs/scan.dat");
  const auto result = runCli("info --json " + shellQuote(file.string()));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const auto json = nlohmann::json::parse(result.out);
  EXPECT_EQ(json.at("points"), 88206);
  EXPECT_EQ(json.at("valid_points"), 88206);
  EXPECT_EQ(json.at("scan_lines"), 491);
  EXPECT_EQ(json.at("points_per_line"), 181);
  EXPECT_EQ(json.at("organised"), false);
  // Its fans turn about the sideways axis (y).
  ASSERT_TRUE(json.contains("tilted_axis")) << result.out;
  EXPECT_GT(std::abs(json.at("tilted_axis").at(1).get<double>()), 0.99) << result.out;
}

TEST(CliInfo, TextOutputNamesTheCounts) {
  CLEARWAY_REAL_SCAN_OR_SKIP(file, "3dtk/scan000.3d");
  const auto result = runCli("info " + shellQuote(file.string()));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("scan_lines:      226"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("organised:       yes"), std::string::npos) << result.out;
  // A nodding scanner: its fans turn about the sideways axis, 0.517 deg apart (SOURCE.txt).
  EXPECT_NE(result.out.find("fans about a tilted axis (nodding)"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("0.517 deg between lines"), std::string::npos) << result.out;
}

TEST(CliInfo, BadFileExitsOneWithAOneLineError) {
  test::TemporaryDirectory directory;
  test::writeBytes(directory / "bad.pcd", "garbage\n");
  const auto result = runCli("info " + shellQuote((directory / "bad.pcd").string()));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_TRUE(result.out.empty()) << "no partial output: " << result.out;
  EXPECT_NE(result.err.find("bad.pcd"), std::string::npos) << result.err;
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
}

TEST(CliInfo, UsageMistakesExitTwo) {
  EXPECT_EQ(runCli("info").exit_code, 2);
  EXPECT_EQ(runCli("info --bogus x.pcd").exit_code, 2);
  EXPECT_EQ(runCli("frobnicate").exit_code, 2);
  EXPECT_EQ(runCli("").exit_code, 2);
  EXPECT_EQ(runCli("info --self-hit-radius abc x.pcd").exit_code, 2);
}

// A partial acquisition's scan says so, as the console's banner does: by its record
// (SCAN.acquisition.json: why it ended), else by the name Clearway gives it. `info` and `segment`
// said nothing, and a scan cut short read as the whole place.
class PartialScan : public test::FileFolderTest {};

TEST_F(PartialScan, InfoAndSegmentSayAScanIsPartialAndWhy) {
  const auto cut = directory / "cut.partial.pcd";
  ASSERT_EQ(runCli("simulate garage --lines 20 -o " + shellQuote(cut.string())).exit_code, 0);
  const auto by_name = runCli("info " + shellQuote(cut.string()));
  EXPECT_NE(by_name.out.find("partial scan: the acquisition ended before the turn was complete"),
            std::string::npos)
      << by_name.out;
  write("cut.partial.acquisition.json",
        R"({"version": 1, "scan": "cut.partial.pcd", "complete": false,)"
        R"( "reason": "stopped by a signal after 12 lines"})");
  const auto by_record = runCli("info --json " + shellQuote(cut.string()));
  EXPECT_NE(by_record.out.find("the acquisition ended early (stopped by a signal after 12 lines)"),
            std::string::npos)
      << by_record.out;
  const auto segmented = runCli("segment " + shellQuote(cut.string()) + " -o " +
                                shellQuote((directory / "r").string()));
  EXPECT_NE(segmented.out.find("caution: partial scan"), std::string::npos) << segmented.out;
  // A record that says complete outweighs the name; a complete scan's name says nothing.
  write("cut.partial.acquisition.json", R"({"version": 1, "complete": true, "reason": ""})");
  EXPECT_EQ(runCli("info " + shellQuote(cut.string())).out.find("partial scan"), std::string::npos);
  const auto whole = directory / "whole.pcd";
  ASSERT_EQ(runCli("simulate garage --lines 20 -o " + shellQuote(whole.string())).exit_code, 0);
  EXPECT_EQ(runCli("info " + shellQuote(whole.string())).out.find("partial scan"),
            std::string::npos);
}

TEST(CliInfo, HelpExitsZero) {
  const auto result = runCli("--help");
  EXPECT_EQ(result.exit_code, 0);
  EXPECT_NE(result.out.find("info"), std::string::npos);
}

// A new user's first tries: `COMMAND --help`, `help COMMAND`, and a wrong option, each answered
// with that command's own usage (they said "unknown option --help" and nothing more).
TEST(CliHelp, EveryCommandAnswersWithItsOwnUsage) {
  const std::vector<std::string> kCommands = {"info",    "simulate", "scene", "segment", "emulate",
                                              "acquire", "serve",    "bench", "eval"};
  for (const std::string& command : kCommands) {
    SCOPED_TRACE(command);
    const std::string own_line = "usage:\n  " + command + " ";
    for (const std::string& asked : {command + " --help", command + " -h", "help " + command}) {
      const auto result = runCli(asked);
      EXPECT_EQ(result.exit_code, 0) << asked << ": " << result.err;
      EXPECT_TRUE(result.out.starts_with(own_line)) << asked << ": " << result.out;
      for (const std::string& other : kCommands) {
        if (other == command) continue;
        EXPECT_EQ(result.out.find("\n  " + other + " "), std::string::npos)
            << "only " << command << "'s lines: " << result.out;
      }
    }
    const auto wrong = runCli(command + " --no-such-option");
    EXPECT_EQ(wrong.exit_code, 2);
    EXPECT_NE(wrong.err.find("--no-such-option"), std::string::npos) << wrong.err;
    EXPECT_NE(wrong.err.find(own_line), std::string::npos) << wrong.err;
  }
  const auto unknown = runCli("help frobnicate");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("unknown command 'frobnicate'"), std::string::npos) << unknown.err;
  const auto version = runCli("--version");
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_TRUE(version.out.starts_with("clearway-cli ")) << version.out;
}

}  // namespace
}  // namespace clearway
