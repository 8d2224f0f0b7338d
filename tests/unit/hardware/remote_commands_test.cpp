// clearway-cli serve and acquire --remote as processes, as an operator runs them.

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

  // Runs acquire --remote; returns the exit code, stderr in `err`.
  int acquire(const QStringList& extra, QString* err) {
    QProcess acquire;
    acquire.start(CLEARWAY_CLI,
                  QStringList{"acquire", "--remote", QString("127.0.0.1:%1").arg(port_)} + extra);
    acquire.waitForFinished(kWaitMs);
    if (err) *err = QString::fromUtf8(acquire.readAllStandardError());
    return acquire.exitCode();
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
