// clearway-cli acquire as an operator runs it, against the emulator: the arm's pose reaches the
// saved scan and the engine, signals and kill -9 lose no line received, bad options and a busy
// port fail before any scan starts.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <thread>

#include "clearway/hardware/rosi_emulator.h"
#include "clearway/io/scan_io.h"
#include "clearway/sim/builtin_scenes.h"
#include "engine_fixtures.h"
#include "test_support.h"

extern char** environ;

namespace clearway {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using test::runCli;
using test::shellQuote;

std::string ports(const hardware::RosiEmulator& emulator) {
  return " --lms " + shellQuote(emulator.lmsPort()) + " --turntable " +
         shellQuote(emulator.turntablePort());
}

// clearway-cli running in the background, its output in files; `launcher` runs it (e.g. a shell
// that limits it first).
class Background {
 public:
  Background(const std::vector<std::string>& arguments, const fs::path& folder,
             const std::vector<std::string>& launcher = {}) {
    std::vector<std::string> words = launcher;
    words.push_back(CLEARWAY_CLI);
    words.insert(words.end(), arguments.begin(), arguments.end());
    std::vector<char*> argv;
    for (std::string& word : words)
      argv.push_back(word.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    out_ = folder / "out.txt";
    err_ = folder / "err.txt";
    posix_spawn_file_actions_addopen(&actions, 1, out_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, 2, err_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    EXPECT_EQ(posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ), 0);
    posix_spawn_file_actions_destroy(&actions);
  }
  ~Background() {
    if (pid_ > 0 && !waited_) {
      ::kill(pid_, SIGKILL);
      wait();
    }
  }
  void signal(int number) { ::kill(pid_, number); }
  // The exit code, or 128 + the signal that ended it.
  int wait() {
    if (!waited_) ::waitpid(pid_, &status_, 0);
    waited_ = true;
    return WIFEXITED(status_) ? WEXITSTATUS(status_) : 128 + WTERMSIG(status_);
  }
  // False once it has ended (wait() then says how).
  bool running() {
    if (waited_) return false;
    if (::waitpid(pid_, &status_, WNOHANG) == 0) return true;
    waited_ = true;
    return false;
  }
  std::string err() const { return test::readBytes(err_); }
  std::string out() const { return test::readBytes(out_); }

 private:
  pid_t pid_ = -1;
  int status_ = 0;
  bool waited_ = false;
  fs::path out_, err_;
};

// Line records in a journal so far (lines ending in '\n' only: a torn one is not counted).
std::size_t journaledLines(const fs::path& journal) {
  std::ifstream in(journal, std::ios::binary);
  std::size_t count = 0;
  std::string line;
  while (std::getline(in, line))
    count += !in.eof() && line.rfind("L ", 0) == 0;
  return count;
}

template <typename Condition>
bool waitFor(Condition condition, int seconds = 30) {
  const auto until = Clock::now() + std::chrono::seconds(seconds);
  while (Clock::now() < until) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

// The scan's VIEWPOINT is `truth` (world_from_scanner), to `tolerance`.
void expectPose(const Scan& scan, const hardware::RigidPose& truth, double tolerance) {
  ASSERT_TRUE(scan.sensor_pose);
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(scan.sensor_pose->position[std::size_t(i)], truth.translation[i], tolerance);
  const Eigen::Matrix3d r = truth.rotation.toRotationMatrix();
  for (int i = 0; i < 9; ++i)
    EXPECT_NEAR(scan.sensor_pose->rotation[std::size_t(i)], r(i / 3, i % 3), tolerance);
}

// The simulator's placement whose pose is `world_from_scanner`, so the engine fixtures can find
// world positions in a map made from an acquired scan.
sim::ScannerPlacement placementOf(const SensorPose& pose) {
  Eigen::Matrix3d r;
  for (int i = 0; i < 9; ++i)
    r(i / 3, i % 3) = pose.rotation[std::size_t(i)];
  sim::ScannerPlacement placement;
  placement.position = {pose.position[0], pose.position[1], pose.position[2]};
  placement.axis = r.col(2);
  const Eigen::Vector3d x0 = placement.worldFromScanner().linear().col(0);
  placement.axis_roll_deg =
      std::atan2(r.col(2).dot(x0.cross(r.col(0))), x0.dot(r.col(0))) * 180 / M_PI;
  return placement;
}

TEST(CliAcquire, TheArmsPoseTravelsWithTheScanAndTheGarageDoorIsJudgedRight) {
  test::TemporaryDirectory directory;
  // In real time (a turn takes 8 s, as on the robot): faster, the host's scheduling delays in
  // stamping lines become degrees of turntable angle on a busy machine, and the 0.9 m door leaves
  // the 0.85 m robot only 2.5 cm a side.
  hardware::EmulatorOptions options{1.0, 3};
  options.arm_tilt_deg = 30;
  options.arm_roll_deg = 60;
  hardware::RosiEmulator emulator(*sim::builtinScene("garage"), options);
  const fs::path scan = directory / "garage.pcd";
  const auto acquired = runCli("acquire" + ports(emulator) + " --arm " +
                               shellQuote(emulator.armPort()) + " -o " + shellQuote(scan.string()));
  ASSERT_EQ(acquired.exit_code, 0) << acquired.err;
  EXPECT_FALSE(fs::exists(directory / "garage.journal"));  // turned into the PCD, then removed

  // The sidecar, with exactly the keys the pose resolution reads.
  const auto sidecar = nlohmann::json::parse(test::readBytes(directory / "garage.pose.json"));
  EXPECT_EQ(sidecar.at("version"), 1);
  EXPECT_EQ(sidecar.at("source"), "arm");
  EXPECT_NEAR(sidecar.at("arm_tilt_deg").get<double>(), 30, 1e-6);
  EXPECT_NEAR(sidecar.at("arm_roll_deg").get<double>(), 60, 1e-6);
  EXPECT_EQ(sidecar.at("world_from_scanner").at("translation").size(), 3u);
  EXPECT_EQ(sidecar.at("world_from_scanner").at("rotation_wxyz").size(), 4u);
  EXPECT_FALSE(sidecar.at("time").get<std::string>().empty());

  // The VIEWPOINT is the pose the emulator really scanned from.
  Scan loaded = loadScan(scan);
  ASSERT_TRUE(loaded.sensor_pose);
  expectPose(loaded, emulator.worldFromScanner(), 1e-5);

  // clearway-cli segment finds the ground of the saved scan.
  const auto segmented = runCli("segment " + shellQuote(scan.string()) + " -o " +
                                shellQuote((directory / "out").string()) + " --robot-width 0.85");
  ASSERT_EQ(segmented.exit_code, 0) << segmented.err;
  const auto report = nlohmann::json::parse(test::readBytes(directory / "out" / "report.json"));
  EXPECT_EQ(report.at("ground_found"), true);
  // The arm's pose gives the robot's frame: its heading is recorded, not guessed.
  EXPECT_EQ(report.at("robot_pose").at("heading"), "recorded");

  // And the door: the 0.85 m robot gets through the 0.9 m door, the 1.0 m one does not.
  const Eigen::Vector3d inside{2.0, -1.0, 0.0}, outside{6.5, -1.0, 0.0};
  for (const double width : {0.85, 1.0}) {
    SCOPED_TRACE(width);
    test::SimulatedRun run;
    run.simulated.truth.placement = placementOf(*loaded.sensor_pose);
    SegmentationParams params;
    params.robot.width = width;
    run.result = runPipeline(loaded, params);
    ASSERT_TRUE(run.result.trusted()) << run.result.reason;
    EXPECT_EQ(test::connectedInMap(run, inside, outside), width < 0.9);
  }
}

// serve on the robot with the arm: every scan it serves carries the pose the emulator scanned
// from, as acquire --arm's do; the simulator has its own pose and refuses the options.
TEST(CliAcquire, ServeWithTheArmServesScansWithTheirPose) {
  test::TemporaryDirectory directory;
  hardware::EmulatorOptions options{4.0, 5};  // 2 s a turn
  options.arm_tilt_deg = -20;
  options.arm_roll_deg = 45;
  hardware::RosiEmulator emulator(*sim::builtinScene("garage"), options);
  const std::string credentials = (directory / "creds").string();
  ASSERT_EQ(runCli("serve --init-credentials " + shellQuote(credentials)).exit_code, 0);

  const auto refused = runCli("serve --credentials " + shellQuote(credentials) +
                              " --listen 127.0.0.1:0 --simulate garage --mount 0,0,1,1,0,0,0");
  EXPECT_NE(refused.exit_code, 0);
  EXPECT_NE(refused.err.find("--arm and --mount are for the serial RoSi"), std::string::npos)
      << refused.err;

  Background serve({"serve", "--credentials", credentials, "--listen", "127.0.0.1:0", "--lms",
                    emulator.lmsPort(), "--turntable", emulator.turntablePort(), "--arm",
                    emulator.armPort(), "--storage", (directory / "robot").string()},
                   directory.path());
  std::string port;
  ASSERT_TRUE(waitFor([&] {
    const std::string out = serve.out();
    const auto at = out.find("127.0.0.1:");
    if (at == std::string::npos) return false;
    port = out.substr(at + 10, out.find(' ', at) - at - 10);
    return true;
  })) << serve.err();
  const fs::path scan = directory / "got.pcd";
  const auto acquired =
      runCli("acquire --remote 127.0.0.1:" + port + " --credentials " + shellQuote(credentials) +
             " --lines 40 -o " + shellQuote(scan.string()));
  ASSERT_EQ(acquired.exit_code, 0) << acquired.err << serve.err();
  const Scan loaded = loadScan(scan);
  ASSERT_TRUE(loaded.sensor_pose);
  expectPose(loaded, emulator.worldFromScanner(), 1e-4);
}

TEST(CliAcquire, SigtermStopsTheDevicesSavesThePartialScanAndTheNextAcquireWorks) {
  test::TemporaryDirectory directory;
  hardware::RosiEmulator emulator(*sim::builtinScene("garage"), {2.0, 3});  // 4 s a turn
  const fs::path scan = directory / "first.pcd";
  Background acquire({"acquire", "--lms", emulator.lmsPort(), "--turntable",
                      emulator.turntablePort(), "-o", scan.string()},
                     directory.path());
  ASSERT_TRUE(waitFor([&] { return journaledLines(directory / "first.journal") >= 20; }));
  acquire.signal(SIGTERM);
  EXPECT_EQ(acquire.wait(), 1);
  EXPECT_NE(acquire.err().find("interrupted by SIGTERM"), std::string::npos) << acquire.err();
  const fs::path partial = directory / "first.partial.pcd";
  ASSERT_TRUE(fs::exists(partial)) << acquire.err();
  EXPECT_FALSE(fs::exists(directory / "first.journal"));
  EXPECT_GE(loadScan(partial).lines.size(), 20u);
  const auto report =
      nlohmann::json::parse(test::readBytes(directory / "first.partial.acquisition.json"));
  EXPECT_EQ(report.at("complete"), false);
  EXPECT_EQ(report.at("stopped_by_signal"), true);
  // The laser's continuous output is off.
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const auto sent = emulator.linesSent();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_EQ(emulator.linesSent(), sent);
  // Right away, the next acquisition works.
  const auto second = runCli("acquire" + ports(emulator) + " --lines 20 -o " +
                             shellQuote((directory / "second.pcd").string()));
  EXPECT_EQ(second.exit_code, 0) << second.err;
  EXPECT_EQ(loadScan(directory / "second.pcd").lines.size(), 20u);
}

// kill -9 at random moments: every line the emulator sent before the kill is in the recovered
// scan. Half the kills hit the acquisition while lines stream (lines sent within the last
// kInFlightMs may still be in the serial buffer, unread, and are excused); the other half hit it
// once the laser has paused and everything sent was read, where the count must match exactly.
TEST(CliAcquire, KillNineAtRandomMomentsLosesNoLineReceived) {
  constexpr int kRuns = 20;
  constexpr int kInFlightMs = 300;
  std::mt19937 random(20261122);
  std::uniform_int_distribution<int> delay_ms(100, 1500);
  std::size_t total_recovered = 0, total_sent = 0;
  for (int run = 0; run < kRuns; ++run) {
    SCOPED_TRACE("run " + std::to_string(run));
    test::TemporaryDirectory directory;
    // 4 s a turn: the kill, at most 1.5 s after the first line, lands mid-scan however late this
    // thread wakes on a loaded machine (at 2 s a turn one scan was done before it, beside a build).
    hardware::RosiEmulator emulator(*sim::builtinScene("garage"), {2.0, std::uint32_t(run)});
    const fs::path scan = directory / "scan.pcd", journal = directory / "scan.journal";
    Background acquire({"acquire", "--lms", emulator.lmsPort(), "--turntable",
                        emulator.turntablePort(), "--timeout", "10000", "-o", scan.string()},
                       directory.path());
    ASSERT_TRUE(waitFor([&] { return journaledLines(journal) >= 1; })) << acquire.err();
    const bool quiet = run % 2 == 1;
    std::vector<std::pair<Clock::time_point, std::uint64_t>> history;
    const auto kill_at = Clock::now() + std::chrono::milliseconds(delay_ms(random));
    while (Clock::now() < kill_at) {
      history.emplace_back(Clock::now(), emulator.linesSent());
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    std::uint64_t sent = 0, surely_read = 0;
    if (quiet) {
      emulator.stallLaser(true);
      // Lines already due or queued when the laser paused still go out: wait until none do.
      do {
        sent = emulator.linesSent();
        std::this_thread::sleep_for(std::chrono::milliseconds(150));
      } while (emulator.linesSent() != sent);
      ASSERT_TRUE(waitFor([&] { return journaledLines(journal) >= sent; })) << sent;
      acquire.signal(SIGKILL);
      surely_read = sent;
    } else {
      sent = emulator.linesSent();
      acquire.signal(SIGKILL);
      for (const auto& [time, count] : history)
        if (time <= kill_at - std::chrono::milliseconds(kInFlightMs)) surely_read = count;
    }
    EXPECT_EQ(acquire.wait(), 128 + SIGKILL);
    // The emulator counts a line once write() has returned, and the kill lands a moment after
    // the count was read: a line may be read before it is counted. Only the count taken once
    // the process is dead bounds what it can have received.
    const std::uint64_t sent_by_death = emulator.linesSent();
    ASSERT_TRUE(fs::exists(journal));
    const auto recovered = runCli("acquire --recover " + shellQuote(journal.string()) + " -o " +
                                  shellQuote(scan.string()));
    EXPECT_EQ(recovered.exit_code, 1) << recovered.err;  // recovered, but incomplete
    ASSERT_TRUE(fs::exists(scan)) << recovered.out << recovered.err;
    const auto report = nlohmann::json::parse(test::readBytes(directory / "scan.acquisition.json"));
    const std::size_t received = report.at("lines_received");
    const std::size_t lines = loadScan(scan).lines.size();
    std::cout << "run " << run << (quiet ? " (laser paused)" : " (streaming)") << ": emulator sent "
              << sent << ", journal held " << received << ", scan has " << lines << " lines\n";
    if (quiet)
      EXPECT_EQ(received, sent);
    else
      EXPECT_GE(received, surely_read);
    EXPECT_LE(received, sent_by_death);
    EXPECT_EQ(lines, received) << "every line received is in the scan";
    total_recovered += lines;
    total_sent += sent;
  }
  std::cout << kRuns << " kills: " << total_recovered << " lines recovered of " << total_sent
            << " sent\n";
}

TEST(CliAcquire, ABadOutputOrBaudFailsBeforeAnyScan) {
  test::TemporaryDirectory directory;
  hardware::RosiEmulator emulator(*sim::builtinScene("garage"), {20.0, 3});
  const auto missing = runCli("acquire" + ports(emulator) + " -o " +
                              shellQuote((directory / "no-such-folder" / "x.pcd").string()));
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("no-such-folder"), std::string::npos) << missing.err;
  EXPECT_NE(missing.err.find("does not exist"), std::string::npos) << missing.err;
  const auto baud = runCli("acquire" + ports(emulator) + " --baud 115200 -o " +
                           shellQuote((directory / "x.pcd").string()));
  EXPECT_EQ(baud.exit_code, 2);
  EXPECT_NE(baud.err.find("115200"), std::string::npos) << baud.err;
  EXPECT_EQ(emulator.linesSent(), 0u);  // the laser was never started
  // A baud rate the LMS200 has is used.
  const auto fast = runCli("acquire" + ports(emulator) + " --baud 500000 --lines 10 -o " +
                           shellQuote((directory / "fast.pcd").string()));
  EXPECT_EQ(fast.exit_code, 0) << fast.err;
  // A scan already acquired, complete or partial, is never written over (it was, silently).
  const std::string before = test::readBytes(directory / "fast.pcd");
  const auto again = runCli("acquire" + ports(emulator) + " --lines 10 -o " +
                            shellQuote((directory / "fast.pcd").string()));
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_NE(again.err.find("never written over"), std::string::npos) << again.err;
  EXPECT_EQ(test::readBytes(directory / "fast.pcd"), before);
  test::writeBytes(directory / "cut.partial.pcd", "lines kept from an interrupted scan");
  const auto beside_partial = runCli("acquire" + ports(emulator) + " --lines 10 -o " +
                                     shellQuote((directory / "cut.pcd").string()));
  EXPECT_EQ(beside_partial.exit_code, 2);
  EXPECT_NE(beside_partial.err.find("cut.partial.pcd"), std::string::npos) << beside_partial.err;
  EXPECT_EQ(test::readBytes(directory / "cut.partial.pcd"), "lines kept from an interrupted scan");
}

TEST(CliAcquire, ASecondAcquireOnTheSamePortsIsToldTheyAreBusy) {
  test::TemporaryDirectory directory;
  hardware::RosiEmulator emulator(*sim::builtinScene("garage"), {1.0, 3});  // 8 s a turn
  Background first({"acquire", "--lms", emulator.lmsPort(), "--turntable", emulator.turntablePort(),
                    "-o", (directory / "first.pcd").string()},
                   directory.path());
  ASSERT_TRUE(waitFor([&] { return journaledLines(directory / "first.journal") >= 1; }));
  const auto second = runCli("acquire" + ports(emulator) + " -o " +
                             shellQuote((directory / "second.pcd").string()));
  EXPECT_EQ(second.exit_code, 1);
  EXPECT_NE(second.err.find("in use by another program"), std::string::npos) << second.err;
  EXPECT_FALSE(fs::exists(directory / "second.pcd"));
  first.signal(SIGINT);
  EXPECT_EQ(first.wait(), 1);
  EXPECT_NE(first.err().find("interrupted by SIGINT"), std::string::npos) << first.err();
}

// One port given for two devices is said as such, before any port is opened (it was "in use by
// another program", the port's lock taken by the same acquisition): by the same name, or by a
// link to it (as /dev/serial/by-id/ names are), for the laser, the turntable or the arm, and by
// serve as by acquire.
TEST(CliAcquire, OnePortGivenForTwoDevicesIsSaidAsSuch) {
  test::TemporaryDirectory directory;
  hardware::RosiEmulator emulator(*sim::builtinScene("garage"), {20.0, 3});
  const std::string lms = shellQuote(emulator.lmsPort());
  const std::string output = " -o " + shellQuote((directory / "x.pcd").string());
  const auto twice = runCli("acquire --lms " + lms + " --turntable " + lms + output);
  EXPECT_EQ(twice.exit_code, 2);
  EXPECT_NE(twice.err.find("the same port was given for --lms and --turntable (" +
                           emulator.lmsPort() + ")"),
            std::string::npos)
      << twice.err;
  EXPECT_EQ(twice.err.find("in use"), std::string::npos) << twice.err;
  const fs::path link = directory / "laser-by-id";
  fs::create_symlink(emulator.lmsPort(), link);
  const auto linked =
      runCli("acquire --lms " + lms + " --turntable " + shellQuote(emulator.turntablePort()) +
             " --arm " + shellQuote(link.string()) + output);
  EXPECT_EQ(linked.exit_code, 2);
  EXPECT_NE(linked.err.find("the same port was given for --lms and --arm"), std::string::npos)
      << linked.err;
  EXPECT_NE(linked.err.find("are both " + fs::canonical(emulator.lmsPort()).string()),
            std::string::npos)
      << linked.err;
  const std::string credentials = shellQuote((directory / "c").string());
  ASSERT_EQ(runCli("serve --init-credentials " + credentials).exit_code, 0);
  // --seconds: were the ports taken as they are, serve would serve, and end by itself.
  const auto served =
      runCli("serve --credentials " + credentials + " --listen 127.0.0.1:0 --seconds 60 --lms " +
             lms + " --turntable " + shellQuote(link.string()));
  EXPECT_EQ(served.exit_code, 2);
  EXPECT_NE(served.err.find("the same port was given for --lms and --turntable"), std::string::npos)
      << served.err;
  EXPECT_EQ(emulator.linesSent(), 0u);  // the laser was never started
  EXPECT_FALSE(fs::exists(directory / "x.pcd"));
}

// A turntable that sends no angle: the lines that came cannot be placed, and the journal that
// holds them as they came is kept (it was deleted with them).
TEST(CliAcquire, LinesWithoutAnAngleAreKeptInTheJournal) {
  test::TemporaryDirectory directory;
  hardware::RosiEmulator emulator(*sim::builtinScene("garage"), {20.0, 3});
  emulator.muteAngles(true);
  const auto muted = runCli("acquire" + ports(emulator) + " --lines 100 --timeout 500 -o " +
                            shellQuote((directory / "muted.pcd").string()));
  EXPECT_EQ(muted.exit_code, 1);
  EXPECT_NE(muted.err.find("turntable"), std::string::npos) << muted.err;
  ASSERT_GT(emulator.linesSent(), 0u);  // the laser streamed; only the angles were missing
  EXPECT_TRUE(fs::exists(directory / "muted.journal")) << muted.err;
  EXPECT_GT(journaledLines(directory / "muted.journal"), 0u);
  EXPECT_NE(muted.err.find("kept as they came"), std::string::npos) << muted.err;
  EXPECT_FALSE(fs::exists(directory / "muted.pcd"));
}

TEST(CliAcquire, DroppedLinesAreReportedAndTheScanIsNotCalledComplete) {
  test::TemporaryDirectory directory;
  hardware::RosiEmulator emulator(*sim::builtinScene("garage"), {20.0, 3});
  emulator.corruptEvery(7);
  const auto result = runCli("acquire" + ports(emulator) + " --lines 50 -o " +
                             shellQuote((directory / "x.pcd").string()));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("dropped"), std::string::npos) << result.err;
  EXPECT_FALSE(fs::exists(directory / "x.pcd"));
  const auto report =
      nlohmann::json::parse(test::readBytes(directory / "x.partial.acquisition.json"));
  EXPECT_GT(report.at("dropped_lines").get<int>(), 0);
  EXPECT_EQ(report.at("complete"), false);
}

// Runs clearway-cli under a file size limit of `kilobytes`: a file it writes that would grow
// beyond it fails with EFBIG ("File too large"), as one on a full disk fails with ENOSPC, with no
// root and no mount. SIGXFSZ is ignored, so the write fails instead of killing the process.
std::vector<std::string> underFileSizeLimit(int kilobytes) {
  return {"/bin/sh", "-c",
          "trap '' XFSZ; ulimit -f " + std::to_string(kilobytes * 2) + "; exec \"$@\"", "sh"};
}

// The disk fills up mid-scan: the operator is told at once, while the scan runs, with the cause
// and the lines the journal holds, and at the end how many of the lines received are kept where
// (here the scan cannot be saved either). Nothing was said until the scan ended, and then not how
// many lines the journal held.
TEST(CliAcquire, AJournalThatFailsMidScanIsToldAtOnceAndTheEndSaysWhatIsKept) {
  test::TemporaryDirectory directory;
  hardware::RosiEmulator emulator(*sim::builtinScene("garage"), {1.0, 3});  // 8 s a turn
  const fs::path scan = directory / "full.pcd", journal = directory / "full.journal";
  // 16 kB: about 15 lines of the journal, and far less than the scan file.
  Background acquire({"acquire", "--lms", emulator.lmsPort(), "--turntable",
                      emulator.turntablePort(), "-o", scan.string()},
                     directory.path(), underFileSizeLimit(16));
  std::uint64_t sent_when_told = 0;
  ASSERT_TRUE(waitFor([&] {
    sent_when_told = emulator.linesSent();
    return acquire.err().find("cannot write the journal") != std::string::npos ||
           !acquire.running();
  })) << acquire.err();
  // A turn is 300 lines: told while the scan runs, not once it has ended.
  EXPECT_LT(sent_when_told, 150u) << acquire.err();
  ASSERT_TRUE(acquire.running()) << acquire.err();
  const std::string told = acquire.err();
  EXPECT_NE(told.find("cannot write the journal " + journal.string() + ": File too large"),
            std::string::npos)
      << told;
  const auto holds = told.find("it holds the first ");
  ASSERT_NE(holds, std::string::npos) << told;
  const std::size_t journaled = std::stoul(told.substr(holds + 19));
  EXPECT_EQ(journaledLines(journal), journaled);

  ASSERT_TRUE(waitFor([&] { return emulator.linesSent() > journaled + 30; }));
  acquire.signal(SIGTERM);
  EXPECT_EQ(acquire.wait(), 1);
  const std::string said = acquire.err();
  EXPECT_NE(said.find("full.partial.pcd: cannot write: File too large"), std::string::npos) << said;
  EXPECT_NE(said.find("only " + std::to_string(journaled) + " of the "), std::string::npos) << said;
  EXPECT_NE(said.find("are kept, in " + journal.string() + ": recover them"), std::string::npos)
      << said;
  EXPECT_NE(said.find("could not be saved"), std::string::npos) << said;
  EXPECT_FALSE(fs::exists(directory / "full.partial.pcd"));
  const auto recovered = runCli("acquire --recover " + shellQuote(journal.string()) + " -o " +
                                shellQuote((directory / "recovered.pcd").string()));
  EXPECT_NE(recovered.out.find("recovered " + std::to_string(journaled) + " lines in the scan"),
            std::string::npos)
      << recovered.out << recovered.err;
}

TEST(CliEmulate, FaultSwitchesAndTheArmAreOnTheCommandLine) {
  test::TemporaryDirectory directory;
  const fs::path ports_file = directory / "ports.json";
  Background emulate({"emulate", "--speed", "20", "--arm-tilt", "30", "--arm-roll", "60",
                      "--mute-angles", "--ports", ports_file.string()},
                     directory.path());
  ASSERT_TRUE(waitFor([&] { return fs::exists(ports_file); }));
  const auto json = nlohmann::json::parse(test::readBytes(ports_file));
  const auto result =
      runCli("acquire --lms " + shellQuote(json.at("lms")) + " --turntable " +
             shellQuote(json.at("turntable")) + " --arm " + shellQuote(json.at("arm")) +
             " --timeout 400 -o " + shellQuote((directory / "x.pcd").string()));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("sends no angles"), std::string::npos) << result.err;
  emulate.signal(SIGTERM);
  EXPECT_EQ(emulate.wait(), 0);
}

}  // namespace
}  // namespace clearway
