// Output that survives a full disk, result folders written as a unit, non-UTF-8 file names and
// parameters that are refused instead of wrapped (issue #12, items 1, 4, 5 and 8).

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "test_support.h"

namespace clearway {
namespace {

namespace fs = std::filesystem;
using test::runCli;
using test::shellQuote;

// Runs a shell script with $CLI set to clearway-cli; stdout and stderr together.
test::CommandResult runShell(const std::string& script) {
  const std::string command =
      "CLI=" + shellQuote(CLEARWAY_CLI) + " sh -c " + shellQuote(script) + " 2>&1";
  test::CommandResult result;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return result;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;)
    result.out.append(buffer, n);
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

std::vector<std::string> entriesOf(const fs::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

bool canMountTmpfs() {
  if (::geteuid() != 0) return false;
  return runShell("unshare -m sh -c 'mount -t tmpfs -o size=64k tmpfs /mnt'").exit_code == 0;
}

// Issue #12.1: PCL's writer memory-mapped the file and died of SIGBUS (exit 135) on a full
// tmpfs, leaving its hidden temporary behind. Now: exit 1, the file named, nothing left.
TEST(FullDisk, PcdOnAFullTmpfsFailsCleanlyInEveryEncoding) {
  if (!canMountTmpfs())
    GTEST_SKIP() << "needs root and unshare -m to mount a 300 kB tmpfs (CI runs as root)";
  test::TemporaryDirectory directory;
  for (const char* encoding : {"binary", "binary_compressed", "ascii"}) {
    const fs::path disk = directory / encoding;
    fs::create_directory(disk);
    const auto result =
        runShell("unshare -m sh -c 'mount -t tmpfs -o size=300k tmpfs " + disk.string() +
                 " && \"$CLI\" simulate garage --lines 423 --encoding " + encoding + " -o " +
                 (disk / "g.pcd").string() + "; echo \"exit=$?\"; ls -A " + disk.string() + "'");
    EXPECT_NE(result.out.find("exit=1"), std::string::npos) << encoding << ": " << result.out;
    EXPECT_NE(result.out.find("g.pcd: cannot write: No space left on device"), std::string::npos)
        << encoding << ": " << result.out;
    EXPECT_EQ(result.out.find(".tmp"), std::string::npos)
        << encoding << ": a temporary was left behind: " << result.out;
  }
}

// The same on any machine: a file size limit (SIGXFSZ ignored) makes write(2) fail with EFBIG.
TEST(FullDisk, PcdBeyondAFileSizeLimitFailsCleanly) {
  test::TemporaryDirectory directory;
  for (const char* encoding : {"binary", "binary_compressed", "ascii"}) {
    const auto result = runShell(
        "trap '' XFSZ; ulimit -f 200; \"$CLI\" simulate garage --lines 423 "
        "--encoding " +
        std::string(encoding) + " -o " + shellQuote((directory / "g.pcd").string()) +
        "; echo \"exit=$?\"");
    EXPECT_NE(result.out.find("exit=1"), std::string::npos) << encoding << ": " << result.out;
    EXPECT_NE(result.out.find("g.pcd: cannot write: File too large"), std::string::npos)
        << encoding << ": " << result.out;
    for (const std::string& name : entriesOf(directory.path()))
      EXPECT_EQ(name.find(".tmp"), std::string::npos) << encoding << ": left behind: " << name;
  }
}

class ResultFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(runCli("simulate garage --lines 120 -o " + shellQuote(scan.string())).exit_code, 0);
  }
  test::CommandResult segment(const fs::path& out, const std::string& extra = "") {
    return runCli("segment --quiet " + shellQuote(scan.string()) + " -o " +
                  shellQuote(out.string()) + " " + extra);
  }
  test::TemporaryDirectory directory;
  fs::path scan = directory / "g.pcd";
  fs::path truth = directory / "g.truth.json";
};

// Issue #12.4: a re-run that fails half-way used to leave new maps beside the old report.
TEST_F(ResultFolder, AFailedRerunLeavesTheOldResultWholeAndNothingElse) {
  const fs::path out = directory / "out";
  ASSERT_EQ(segment(out, "--robot-width 0.85").exit_code, 0);
  std::map<std::string, std::string> before;
  for (const std::string& name : entriesOf(out))
    before[name] = test::readBytes(out / name);
  ASSERT_TRUE(before.count("report.json") && before.count("manifest.json"));

  // 40 kB is more than the small maps and less than the largest file of a result.
  const auto result =
      runShell("trap '' XFSZ; ulimit -f 40; \"$CLI\" segment --quiet " + shellQuote(scan.string()) +
               " -o " + shellQuote(out.string()) + " --robot-width 1.0; echo \"exit=$?\"");
  ASSERT_NE(result.out.find("exit=1"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("File too large"), std::string::npos) << result.out;
  std::map<std::string, std::string> after;
  for (const std::string& name : entriesOf(out))
    after[name] = test::readBytes(out / name);
  EXPECT_TRUE(before == after) << "the old result folder changed";
  EXPECT_EQ(entriesOf(directory.path()), (std::vector<std::string>{"g.pcd", "g.truth.json", "out"}))
      << "a staging folder was left behind";
  const auto evaluation =
      runCli("eval " + shellQuote(truth.string()) + " " + shellQuote(out.string()));
  EXPECT_EQ(evaluation.exit_code, 0) << evaluation.err;
}

TEST_F(ResultFolder, ASuccessfulRerunReplacesEveryFile) {
  const fs::path out = directory / "out";
  ASSERT_EQ(segment(out, "--robot-width 0.85").exit_code, 0);
  test::writeBytes(out / "stale.txt", "from an older run");
  ASSERT_EQ(segment(out, "--robot-width 1.0").exit_code, 0);
  EXPECT_FALSE(fs::exists(out / "stale.txt"));
  const auto report = nlohmann::json::parse(test::readBytes(out / "report.json"));
  EXPECT_DOUBLE_EQ(report.at("robot").at("width").get<double>(), 1.0);
  EXPECT_EQ(entriesOf(directory.path()),
            (std::vector<std::string>{"g.pcd", "g.truth.json", "out"}));
}

TEST_F(ResultFolder, EvalRefusesAFolderMixingTwoRuns) {
  const fs::path first = directory / "first", second = directory / "second";
  ASSERT_EQ(segment(first, "--robot-width 0.85").exit_code, 0);
  ASSERT_EQ(segment(second, "--robot-width 1.0 --max-step 0.05").exit_code, 0);
  ASSERT_NE(test::readBytes(first / "report.json"), test::readBytes(second / "report.json"));
  fs::copy_file(second / "report.json", first / "report.json",
                fs::copy_options::overwrite_existing);
  const auto mixed =
      runCli("eval " + shellQuote(truth.string()) + " " + shellQuote(first.string()));
  EXPECT_EQ(mixed.exit_code, 1);
  EXPECT_NE(mixed.err.find("report.json"), std::string::npos) << mixed.err;
  EXPECT_NE(mixed.err.find("mixes two results"), std::string::npos) << mixed.err;

  fs::remove(second / "manifest.json");
  const auto unlisted =
      runCli("eval " + shellQuote(truth.string()) + " " + shellQuote(second.string()));
  EXPECT_EQ(unlisted.exit_code, 1);
  EXPECT_NE(unlisted.err.find("manifest.json"), std::string::npos) << unlisted.err;
}

// Issue #12.5: a Latin-1 name made the JSON writer throw after 7 of 8 files, without a file name.
TEST(NonUtf8Names, SegmentWritesEveryFileAndNamesTheScanLosslessly) {
  test::TemporaryDirectory directory;
  const std::string latin1 = "Kellergescho\xDF";  // "Kellergeschoß" in Latin-1
  const fs::path scan = directory / (latin1 + ".pcd");
  const auto simulated = runCli("simulate garage --lines 60 -o " + shellQuote(scan.string()));
  ASSERT_EQ(simulated.exit_code, 0) << simulated.err;
  const fs::path out = directory / (latin1 + "-result");
  const auto result =
      runCli("segment --quiet " + shellQuote(scan.string()) + " -o " + shellQuote(out.string()));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  for (const char* name : {"labels.pgm", "reasons.pgm", "map.pgm", "map.yaml", "traversability.png",
                           "scene.ply", "point_classes.u8", "report.json", "manifest.json"})
    EXPECT_TRUE(fs::exists(out / name)) << name;
  const auto report = nlohmann::json::parse(test::readBytes(out / "report.json"));
  EXPECT_EQ(report.at("scan").get<std::string>(), "Kellergescho\\xDF.pcd");

  const auto info = runCli("info --json " + shellQuote(scan.string()));
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_EQ(nlohmann::json::parse(info.out).at("file").get<std::string>(),
            (directory / "Kellergescho\\xDF.pcd").string());

  const fs::path missing = directory / (latin1 + "-missing.pcd");
  const auto failed = runCli("segment " + shellQuote(missing.string()) + " -o " +
                             shellQuote((directory / "x").string()));
  EXPECT_EQ(failed.exit_code, 1);
  EXPECT_NE(failed.err.find(missing.string()), std::string::npos) << failed.err;
}

// Issue #12.8: 4294967298 became 2 through an int cast; 1e-300 was printed as 0.000000.
TEST(ParameterRanges, OutOfRangeIntegersAreRefusedAndValuesPrintedReadably) {
  test::TemporaryDirectory directory;
  const auto scan = (directory / "g.pcd").string();
  ASSERT_EQ(runCli("simulate garage --lines 30 -o " + shellQuote(scan)).exit_code, 0);
  const auto params = directory / "p.json";
  test::writeBytes(params, R"({"lines": {"min_points": 4294967298}})");
  auto result =
      runCli("segment " + shellQuote(scan) + " -o " + shellQuote((directory / "o").string()) +
             " --params " + shellQuote(params.string()));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("lines.min_points = 4294967298 is outside 2 .. 1000"),
            std::string::npos)
      << result.err;

  test::writeBytes(params, R"({"lines": {"max_deviation": 1e-300}})");
  result = runCli("segment " + shellQuote(scan) + " -o " + shellQuote((directory / "o").string()) +
                  " --params " + shellQuote(params.string()));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("lines.max_deviation = 1e-300 is outside 0.001 .. 1"),
            std::string::npos)
      << result.err;

  result = runCli("segment " + shellQuote(scan) + " -o " + shellQuote((directory / "o").string()) +
                  " --max-slope 1e300");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("--max-slope 1e300 is outside 0 .. 89"), std::string::npos)
      << result.err;
  EXPECT_FALSE(fs::exists(directory / "o"));
}

}  // namespace
}  // namespace clearway
