#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

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
