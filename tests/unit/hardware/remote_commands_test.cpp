// clearway-cli serve and acquire --remote as processes, as an operator runs them.

#include <QRegularExpression>
#include <QThread>
#include <fstream>
#include <string>

#include "clearway/hardware/rosi_emulator.h"
#include "remote_test_support.h"

namespace clearway::hardware::remote {
namespace {

// clearway-cli serve and acquire --remote as an operator runs them, as processes.
class RemoteCommands : public ::testing::Test {
 protected:
  void SetUp() override {
    application();
    ASSERT_TRUE(dir_.isValid());
    credentials_ = dir_.filePath("creds");
    ASSERT_EQ(QProcess::execute(CLEARWAY_CLI, {"serve", "--init-credentials", credentials_}), 0);
    serve_.start(CLEARWAY_CLI,
                 {"serve", "--credentials", credentials_, "--listen", "127.0.0.1:0", "--simulate",
                  "garage", "--speed", "50", "--storage", dir_.filePath("robot")});
    ASSERT_TRUE(serve_.waitForStarted(kWaitMs));
    ASSERT_TRUE(waitFor([&] { return serve_.canReadLine() || serve_.waitForReadyRead(100); }));
    const QString line = QString::fromUtf8(serve_.readLine());
    port_ = line.section("127.0.0.1:", 1).section(' ', 0, 0).toInt();
    ASSERT_GT(port_, 0) << line.toStdString();
  }
  void TearDown() override {
    serve_.terminate();
    serve_.waitForFinished(kWaitMs);
  }

  // Runs acquire --remote against `robot` (HOST:PORT); returns the exit code (-1 if it did not end
  // in time), stderr in `err`.
  static int acquireFrom(const QString& robot, const QStringList& extra, QString* err) {
    QProcess acquire;
    acquire.start(CLEARWAY_CLI, QStringList{"acquire", "--remote", robot} + extra);
    const bool ended = acquire.waitForFinished(kWaitMs);
    if (err) *err = QString::fromUtf8(acquire.readAllStandardError());
    return ended ? acquire.exitCode() : -1;
  }
  // The same against the fixture's robot.
  int acquire(const QStringList& extra, QString* err) {
    return acquireFrom(QString("127.0.0.1:%1").arg(port_), extra, err);
  }

  // Starts `serve` with `arguments` (after "serve --credentials ... --listen 127.0.0.1:0"), run
  // by `launcher` when given (e.g. a shell that limits it first); its HOST:PORT once it listens,
  // empty on failure.
  QString startRobot(QProcess& serve, const QStringList& arguments,
                     const QStringList& launcher = {}) {
    const QStringList command = QStringList{CLEARWAY_CLI, "serve",    "--credentials",
                                            credentials_, "--listen", "127.0.0.1:0"} +
                                arguments;
    if (launcher.isEmpty())
      serve.start(command.front(), command.mid(1));
    else
      serve.start(launcher.front(), launcher.mid(1) + command);
    if (!serve.waitForStarted(kWaitMs) ||
        !waitFor([&] { return serve.canReadLine() || serve.waitForReadyRead(100); }))
      return {};
    const QString port =
        QString::fromUtf8(serve.readLine()).section("127.0.0.1:", 1).section(' ', 0, 0);
    return port.toInt() > 0 ? "127.0.0.1:" + port : QString();
  }

  // Starts a serve of its own scanning in real time (the fixture's runs 50 times faster, done
  // before a test can interrupt it), saving into `storage`; its HOST:PORT, empty on failure.
  QString startRealTimeRobot(QProcess& serve, const QString& storage) {
    return startRobot(serve, {"--simulate", "garage", "--storage", dir_.filePath(storage)});
  }

  // Scan lines in a saved PCD (every return kept: none is the robot's own).
  static std::size_t linesIn(const QString& path) {
    LoadOptions load;
    load.self_hit_radius = 0.0;
    return loadScan(path.toStdString(), load).lines.size();
  }

  // Waits until `process`'s standard error, gathered into `err`, holds `text`.
  static bool waitForError(QProcess& process, const QString& text, QString& err) {
    return waitFor([&] {
      process.waitForReadyRead(100);
      err += QString::fromUtf8(process.readAllStandardError());
      return err.contains(text);
    });
  }

  QTemporaryDir dir_;
  QString credentials_;
  QProcess serve_;
  int port_ = 0;
};

TEST_F(RemoteCommands, AcquireRemoteWritesTheSimulatorsScan) {
  const QString output = dir_.filePath("got.pcd");
  QString err;
  ASSERT_EQ(acquire({"--credentials", credentials_, "--lines", "423", "-o", output}, &err), 0)
      << err.toStdString();
  LoadOptions load;
  load.self_hit_radius = 0.0;
  const Scan got = loadScan(output.toStdString(), load);
  const Scan expected = simulatorScan(kGarageLines);
  ASSERT_EQ(got.lines.size(), expected.lines.size());
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    ASSERT_EQ(got.isValid(i), expected.isValid(i)) << i;
    if (!expected.isValid(i)) continue;
    ASSERT_NEAR(got.points[i].x, expected.points[i].x, kWireResolutionM) << i;
    ASSERT_NEAR(got.points[i].z, expected.points[i].z, kWireResolutionM) << i;
  }
  EXPECT_EQ(QDir(dir_.filePath("robot")).entryList({"scan-*.pcd"}).size(), 1);
}

// Ctrl-C or SIGTERM on a remote scan: the robot is told to stop, and the lines that arrived are
// kept (the process used to die with them, and the robot scanned on).
TEST_F(RemoteCommands, SigtermOnARemoteScanKeepsTheLinesThatArrived) {
  QProcess slow_serve;
  const QString robot = startRealTimeRobot(slow_serve, "slow-robot");
  ASSERT_FALSE(robot.isEmpty());
  const QString output = dir_.filePath("cut.pcd");
  QProcess acquire;
  acquire.setProcessChannelMode(QProcess::SeparateChannels);
  acquire.start(CLEARWAY_CLI, {"acquire", "--remote", robot, "--credentials", credentials_,
                               "--lines", "423", "-o", output});
  ASSERT_TRUE(acquire.waitForStarted(kWaitMs));
  QString err;
  ASSERT_TRUE(waitForError(acquire, "link: ", err));
  QThread::msleep(2500);  // lines stream
  acquire.terminate();    // SIGTERM
  ASSERT_TRUE(acquire.waitForFinished(kWaitMs));
  err += QString::fromUtf8(acquire.readAllStandardError());
  slow_serve.terminate();
  slow_serve.waitForFinished(kWaitMs);
  EXPECT_EQ(acquire.exitStatus(), QProcess::NormalExit) << err.toStdString();
  EXPECT_EQ(acquire.exitCode(), 1) << err.toStdString();
  EXPECT_TRUE(err.contains("interrupted by SIGTERM")) << err.toStdString();
  EXPECT_FALSE(QFile::exists(output));
  const QString partial = dir_.filePath("cut.partial.pcd");
  ASSERT_TRUE(QFile::exists(partial)) << err.toStdString();
  EXPECT_GT(linesIn(partial), 0u);
  EXPECT_LT(linesIn(partial), std::size_t(kGarageLines));
}

// serve stopped during a scan cancels it and saves the lines it has before it ends (it used to end
// with them).
TEST_F(RemoteCommands, ServeStoppedDuringAScanSavesItsLinesFirst) {
  QProcess slow_serve;
  const QString robot = startRealTimeRobot(slow_serve, "slow-robot");
  ASSERT_FALSE(robot.isEmpty());
  QProcess acquire;
  acquire.start(CLEARWAY_CLI,
                {"acquire", "--remote", robot, "--credentials", credentials_, "--lines", "423",
                 "--give-up", "3", "-o", dir_.filePath("client.pcd")});
  ASSERT_TRUE(acquire.waitForStarted(kWaitMs));
  QString err;
  ASSERT_TRUE(waitForError(acquire, "link: connected", err)) << err.toStdString();
  QThread::msleep(2500);  // lines stream
  slow_serve.terminate();
  ASSERT_TRUE(slow_serve.waitForFinished(kWaitMs));
  const QString log = QString::fromUtf8(slow_serve.readAllStandardError());
  acquire.waitForFinished(kWaitMs);
  const QStringList saved = QDir(dir_.filePath("slow-robot")).entryList({"scan-*-partial.pcd"});
  ASSERT_EQ(saved.size(), 1) << log.toStdString();
  const QString kept = QDir(dir_.filePath("slow-robot")).filePath(saved.front());
  EXPECT_GT(linesIn(kept), 0u);
  EXPECT_LT(linesIn(kept), std::size_t(kGarageLines));
}

// Journaled line records in a file (complete ones: a torn last line is not counted).
std::size_t journaledLines(const QString& journal) {
  std::ifstream in(journal.toStdString(), std::ios::binary);
  std::size_t count = 0;
  std::string line;
  while (std::getline(in, line))
    count += !in.eof() && line.rfind("L ", 0) == 0;
  return count;
}

// serve on a real (emulated, serial) RoSi killed with SIGKILL mid-scan, as a power cut would:
// the lines it had received were journaled in its storage folder, and serve recovers them when
// it starts again (they used to be lost: only the scan's end saved anything).
TEST_F(RemoteCommands, ServeKilledDuringAScanRecoversItsLinesWhenItStartsAgain) {
  RosiEmulator emulator(*sim::builtinScene("garage"), {4.0, 7});
  const QString storage = dir_.filePath("serial-robot");
  const QStringList serial_robot = {"--lms",       QString::fromStdString(emulator.lmsPort()),
                                    "--turntable", QString::fromStdString(emulator.turntablePort()),
                                    "--storage",   storage};
  QProcess serve;
  const QString robot = startRobot(serve, serial_robot);
  ASSERT_FALSE(robot.isEmpty());
  QProcess acquire;
  acquire.start(CLEARWAY_CLI, {"acquire", "--remote", robot, "--credentials", credentials_,
                               "--lines", "423", "--give-up", "3", "-o", dir_.filePath("c.pcd")});
  ASSERT_TRUE(acquire.waitForStarted(kWaitMs));
  QString journal;
  ASSERT_TRUE(waitFor([&] {
    const QStringList journals = QDir(storage).entryList({"scan-*.journal"});
    if (journals.isEmpty()) return false;
    journal = QDir(storage).filePath(journals.front());
    return journaledLines(journal) >= 20;
  })) << QString::fromUtf8(serve.readAllStandardError()).toStdString();
  serve.kill();  // SIGKILL: no handler runs, nothing is saved on the way out
  ASSERT_TRUE(serve.waitForFinished(kWaitMs));
  const std::size_t journaled = journaledLines(journal);
  acquire.kill();
  acquire.waitForFinished(kWaitMs);
  EXPECT_TRUE(QDir(storage).entryList({"scan-*.pcd"}).isEmpty()) << "nothing was saved";

  QProcess again;
  const QString restarted = startRobot(again, serial_robot);
  ASSERT_FALSE(restarted.isEmpty());
  // The restarted robot scans (the laser it left streaming is stopped first), and a scan that
  // finishes leaves its file and no journal.
  QProcess complete;
  complete.start(CLEARWAY_CLI, {"acquire", "--remote", restarted, "--credentials", credentials_,
                                "--lines", "100", "-o", dir_.filePath("complete.pcd")});
  if (!complete.waitForFinished(kWaitMs)) {
    again.terminate();
    again.waitForFinished(kWaitMs);
    FAIL() << complete.readAllStandardError().toStdString() << "\nserve:\n"
           << again.readAllStandardError().toStdString();
  }
  EXPECT_EQ(complete.exitCode(), 0) << complete.readAllStandardError().toStdString();
  EXPECT_TRUE(QDir(storage).entryList({"scan-*.journal"}).isEmpty());
  again.terminate();
  again.waitForFinished(kWaitMs);
  const QString log = QString::fromUtf8(again.readAllStandardError());
  const QStringList recovered = QDir(storage).entryList({"scan-*-recovered.pcd"});
  ASSERT_EQ(recovered.size(), 1) << log.toStdString();
  EXPECT_EQ(QDir(storage).entryList({"scan-*.pcd"}).size(), 2);  // and the complete one
  EXPECT_TRUE(log.contains("recovered " + QFileInfo(journal).fileName())) << log.toStdString();
  EXPECT_FALSE(QFile::exists(journal)) << "removed once its scan was saved";
  // Every line journaled before the kill is in the scan (lines the laser sent between the count
  // and the kill may add a few).
  const std::size_t lines = linesIn(QDir(storage).filePath(recovered.front()));
  EXPECT_GE(lines, journaled);
  EXPECT_LT(lines, std::size_t(kGarageLines));
}

// Lines that came without a turntable angle cannot be placed: the scan fails with nothing to
// save, and the robot keeps their journal (as acquire does) instead of removing it.
TEST_F(RemoteCommands, LinesWithoutAnAngleAreKeptInTheRobotsJournal) {
  RosiEmulator emulator(*sim::builtinScene("garage"), {20.0, 3});
  emulator.muteAngles(true);
  const QString storage = dir_.filePath("muted-robot");
  QProcess serve;
  const QString robot =
      startRobot(serve, {"--lms", QString::fromStdString(emulator.lmsPort()), "--turntable",
                         QString::fromStdString(emulator.turntablePort()), "--storage", storage});
  ASSERT_FALSE(robot.isEmpty());
  QString err;
  EXPECT_EQ(acquireFrom(
                robot,
                {"--credentials", credentials_, "--lines", "100", "-o", dir_.filePath("muted.pcd")},
                &err),
            1)
      << err.toStdString();
  EXPECT_TRUE(err.contains("turntable")) << err.toStdString();
  serve.terminate();
  serve.waitForFinished(kWaitMs);
  const QString log = QString::fromUtf8(serve.readAllStandardError());
  EXPECT_TRUE(QDir(storage).entryList({"scan-*.pcd"}).isEmpty()) << log.toStdString();
  const QStringList journals = QDir(storage).entryList({"scan-*.journal"});
  ASSERT_EQ(journals.size(), 1) << log.toStdString();
  EXPECT_GT(journaledLines(QDir(storage).filePath(journals.front())), 0u);
  EXPECT_TRUE(log.contains("holds lines the scan could not place")) << log.toStdString();
}

// The robot's storage fills up mid-scan (here serve runs under a 16 kB file size limit: EFBIG, as
// ENOSPC on a full disk, without root): the console and the log are told at once, with the cause
// and the lines the journal holds. The scan cannot be saved on the robot either: the console is
// told so and how many lines the robot's journal keeps, and keeps every line itself. Nothing was
// said while the scan ran, the console heard its lines were "kept" in the journal (a third of
// them were), and the log blamed lines "the scan could not place".
TEST_F(RemoteCommands, ARobotWhoseDiskFillsUpSaysSoAtOnceAndNamesTheCause) {
  RosiEmulator emulator(*sim::builtinScene("garage"), {2.0, 3});  // 4 s a turn of 300 lines
  const QString storage = dir_.filePath("full-robot");
  QProcess serve;
  const QString robot =
      startRobot(serve,
                 {"--lms", QString::fromStdString(emulator.lmsPort()), "--turntable",
                  QString::fromStdString(emulator.turntablePort()), "--storage", storage},
                 {"/bin/sh", "-c", "trap '' XFSZ; ulimit -f 32; exec \"$@\"", "sh"});
  ASSERT_FALSE(robot.isEmpty());
  QProcess acquire;
  acquire.start(CLEARWAY_CLI, {"acquire", "--remote", robot, "--credentials", credentials_, "-o",
                               dir_.filePath("full.pcd")});
  ASSERT_TRUE(acquire.waitForStarted(kWaitMs));
  QString err;
  std::uint64_t sent_when_told = 0;
  ASSERT_TRUE(waitFor([&] {
    acquire.waitForReadyRead(20);
    err += QString::fromUtf8(acquire.readAllStandardError());
    sent_when_told = emulator.linesSent();
    return err.contains("robot: ") || acquire.state() == QProcess::NotRunning;
  }));
  EXPECT_LT(sent_when_told, 200u) << "told once the scan had ended: " << err.toStdString();
  acquire.waitForFinished(kWaitMs);
  ASSERT_EQ(acquire.state(), QProcess::NotRunning);
  err += QString::fromUtf8(acquire.readAllStandardError());
  EXPECT_EQ(acquire.exitCode(), 1) << err.toStdString();
  EXPECT_TRUE(err.contains(QRegularExpression(
      "robot: cannot write the journal [^ ]*scan-[0-9]*\\.journal: File too large: the journal "
      "holds the first [0-9]+ lines")))
      << err.toStdString();
  EXPECT_TRUE(err.contains(QRegularExpression(
      "The robot could not save the scan: [^ ]*: cannot write: File too large \\([^ ]*\\.journal "
      "keeps [0-9]+ of its [0-9]+ lines\\)")))
      << err.toStdString();
  EXPECT_GT(linesIn(dir_.filePath("full.partial.pcd")), 250u) << "the console keeps every line";
  serve.terminate();
  ASSERT_TRUE(serve.waitForFinished(kWaitMs));
  const QString log = QString::fromUtf8(serve.readAllStandardError());
  EXPECT_TRUE(log.contains("scanner: cannot write the journal")) << log.toStdString();
  EXPECT_TRUE(
      log.contains(QRegularExpression("incomplete: [0-9]+ lines: The robot could not save "
                                      "the scan: [^ ]*: cannot write: File too large")))
      << log.toStdString();
  EXPECT_TRUE(log.contains("the scan could not be saved")) << log.toStdString();
  EXPECT_FALSE(log.contains("could not place")) << log.toStdString();
}

// A scan that fails before any line arrives (here a "laser" that never answers) ends with the
// reason on the console, and the robot takes the next scan. The console used to wait forever,
// and the server refused every later scan as "not ready".
TEST_F(RemoteCommands, AScanThatFailsAtItsStartEndsWithTheReasonAndTheNextMayStart) {
  // Two files that never answer stand for the two devices' ports.
  for (const char* port : {"laser", "table"}) {
    QFile file(dir_.filePath(port));
    ASSERT_TRUE(file.open(QIODevice::WriteOnly));
  }
  QProcess serve;
  const QString robot =
      startRobot(serve, {"--lms", dir_.filePath("laser"), "--turntable", dir_.filePath("table"),
                         "--storage", dir_.filePath("silent-robot")});
  ASSERT_FALSE(robot.isEmpty());
  for (int attempt = 0; attempt < 2; ++attempt) {
    QString err;
    EXPECT_EQ(acquireFrom(robot,
                          {"--credentials", credentials_, "--lines", "50", "-o",
                           dir_.filePath(QString("silent-%1.pcd").arg(attempt))},
                          &err),
              1)
        << "attempt " << attempt << ": " << err.toStdString();
    EXPECT_TRUE(err.contains("is not a serial port")) << err.toStdString();
  }
  serve.terminate();
  serve.waitForFinished(kWaitMs);
}

// A second console asking for control while one has it is told so at once (it waited forever).
TEST_F(RemoteCommands, ASecondControllerIsToldAnotherConsoleControls) {
  QProcess slow_serve;
  const QString robot = startRealTimeRobot(slow_serve, "slow-robot");
  ASSERT_FALSE(robot.isEmpty());
  QProcess first;
  first.start(CLEARWAY_CLI, {"acquire", "--remote", robot, "--credentials", credentials_, "--lines",
                             "423", "-o", dir_.filePath("first.pcd")});
  ASSERT_TRUE(first.waitForStarted(kWaitMs));
  QString first_err;
  ASSERT_TRUE(waitForError(first, "in control", first_err)) << first_err.toStdString();
  QString err;
  EXPECT_EQ(acquireFrom(
                robot,
                {"--credentials", credentials_, "--lines", "40", "-o", dir_.filePath("second.pcd")},
                &err),
            1)
      << err.toStdString();
  EXPECT_TRUE(err.contains("another console controls the scanner")) << err.toStdString();
  EXPECT_FALSE(QFile::exists(dir_.filePath("second.pcd")));
  first.terminate();
  first.waitForFinished(kWaitMs);
  slow_serve.terminate();
  slow_serve.waitForFinished(kWaitMs);
}

// acquire --remote --watch started while another console's scan runs receives and saves that
// scan (it printed "connected (watching)" and then nothing, until it was killed).
TEST_F(RemoteCommands, AWatcherStartedDuringAScanSavesThatScan) {
  QProcess slow_serve;
  const QString robot = startRealTimeRobot(slow_serve, "slow-robot");
  ASSERT_FALSE(robot.isEmpty());
  QProcess controller;
  controller.start(CLEARWAY_CLI, {"acquire", "--remote", robot, "--credentials", credentials_,
                                  "--lines", "423", "-o", dir_.filePath("controller.pcd")});
  ASSERT_TRUE(controller.waitForStarted(kWaitMs));
  QString serve_log;
  ASSERT_TRUE(waitForError(slow_serve, "started (423 lines)", serve_log))
      << serve_log.toStdString();
  QString err;
  const int watched = acquireFrom(
      robot, {"--credentials", credentials_, "--watch", "-o", dir_.filePath("watcher.pcd")}, &err);
  ASSERT_TRUE(controller.waitForFinished(kWaitMs));
  slow_serve.terminate();
  slow_serve.waitForFinished(kWaitMs);
  EXPECT_EQ(controller.exitCode(), 0) << controller.readAllStandardError().toStdString();
  ASSERT_EQ(watched, 0) << err.toStdString();
  EXPECT_TRUE(err.contains("A scan is under way on the robot: receiving it from its first line"))
      << err.toStdString();
  EXPECT_EQ(linesIn(dir_.filePath("watcher.pcd")), std::size_t(kGarageLines));
  EXPECT_EQ(linesIn(dir_.filePath("controller.pcd")), std::size_t(kGarageLines));
}

// Nothing listening and an unknown host are said as such (both were "the credentials may be
// wrong"); wrong credentials are in AcquireRemoteWithWrongCredentialsFailsWithTheReason.
TEST_F(RemoteCommands, AcquireRemoteSaysWhyItCannotConnect) {
  quint16 closed_port = 0;
  {
    QTcpServer gone;
    ASSERT_TRUE(gone.listen(QHostAddress::LocalHost, 0));
    closed_port = gone.serverPort();
  }
  const QString closed = QString("127.0.0.1:%1").arg(closed_port);
  QString err;
  EXPECT_EQ(
      acquireFrom(closed, {"--credentials", credentials_, "-o", dir_.filePath("no.pcd")}, &err), 1);
  EXPECT_TRUE(err.contains("nothing listens at " + closed)) << err.toStdString();
  EXPECT_FALSE(err.contains("credentials")) << err.toStdString();
  EXPECT_EQ(acquireFrom("no-such-robot.invalid:47100",
                        {"--credentials", credentials_, "-o", dir_.filePath("no.pcd")}, &err),
            1);
  EXPECT_TRUE(err.contains("host not found")) << err.toStdString();
  EXPECT_FALSE(err.contains("credentials")) << err.toStdString();
  EXPECT_FALSE(QFile::exists(dir_.filePath("no.pcd")));
}

// The output is checked before the robot scans, as for a serial acquisition.
TEST_F(RemoteCommands, AcquireRemoteChecksItsOutputBeforeScanning) {
  QString err;
  EXPECT_EQ(acquire({"--credentials", credentials_, "-o", dir_.filePath("none/x.pcd")}, &err), 2);
  EXPECT_TRUE(err.contains("does not exist")) << err.toStdString();
  EXPECT_EQ(acquire({"--credentials", credentials_, "-o", dir_.filePath("x.txt")}, &err), 2);
  EXPECT_TRUE(err.contains(".pcd")) << err.toStdString();
  EXPECT_FALSE(QDir(dir_.filePath("robot")).exists() &&
               !QDir(dir_.filePath("robot")).entryList({"scan-*.pcd"}).isEmpty());
}

TEST_F(RemoteCommands, AcquireRemoteWithWrongCredentialsFailsWithTheReason) {
  QTemporaryDir other;
  ASSERT_EQ(QProcess::execute(CLEARWAY_CLI, {"serve", "--init-credentials", other.path()}), 0);
  QString err;
  EXPECT_EQ(acquire({"--credentials", other.path(), "-o", dir_.filePath("no.pcd")}, &err), 1);
  EXPECT_TRUE(err.contains("credentials")) << err.toStdString();
  EXPECT_FALSE(QFile::exists(dir_.filePath("no.pcd")));
  EXPECT_EQ(
      acquire({"--credentials", dir_.filePath("missing"), "-o", dir_.filePath("no.pcd")}, &err), 1);
  EXPECT_TRUE(err.contains("console.json")) << err.toStdString();
}

}  // namespace
}  // namespace clearway::hardware::remote
