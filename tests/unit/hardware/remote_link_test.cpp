// `serve` and the remote RoSi over loopback only (127.0.0.1): a scan end to end equal to the
// simulator's, a link cut mid-scan and resumed, a 1 Mbit/s link, refusals (no credentials, wrong
// credentials, a second controlling console, an old protocol version) and 10,000 malformed frames
// while a good console keeps being served. Waits are bounded in time (to avoid hangs, never as
// assertions on speed).

#include <gtest/gtest.h>

#include <QCoreApplication>
#include <QDir>
#include <QElapsedTimer>
#include <QProcess>
#include <QRandomGenerator>
#include <QSslPreSharedKeyAuthenticator>
#include <QSslSocket>
#include <QTcpServer>
#include <QTcpSocket>
#include <QTemporaryDir>
#include <QTimer>
#include <QtEndian>
#include <cmath>
#include <functional>

#include "clearway/hardware/remote_rosi.h"
#include "clearway/hardware/remote_server.h"
#include "clearway/hardware/simulated_rosi.h"
#include "clearway/io/scan_io.h"
#include "clearway/sim/builtin_scenes.h"
#include "clearway/sim/rosi_simulator.h"

namespace clearway::hardware::remote {
namespace {

constexpr int kGarageLines = 423;  // 76,140 points
constexpr double kWireResolutionM = 0.0005 + 1e-6;
constexpr int kWaitMs = 60000;  // a hung test fails after this instead of hanging

QCoreApplication* application() {
  static int argc = 1;
  static char name[] = "hardware_remote_tests";
  static char* argv[] = {name, nullptr};
  static auto* app = new QCoreApplication(argc, argv);
  return app;
}

// Runs the event loop until `done` or `timeout_ms`; returns done().
bool waitFor(const std::function<bool()>& done, int timeout_ms = kWaitMs) {
  QElapsedTimer clock;
  clock.start();
  while (!done() && clock.elapsed() < timeout_ms)
    QCoreApplication::processEvents(QEventLoop::AllEvents | QEventLoop::WaitForMoreEvents, 10);
  return done();
}

Scan simulatorScan(int lines) {
  sim::SensorModel sensor;
  sensor.lines = lines;
  const sim::Scene scene = *sim::builtinScene("garage");
  return sim::simulateRosi(scene, sensor, sim::defaultPlacement(scene)).scan;
}

// Point for point: same lines, betas, statuses and alphas; coordinates to the wire's 1 mm.
void expectSameScan(const Scan& got, const Scan& expected) {
  ASSERT_EQ(got.lines.size(), expected.lines.size());
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t l = 0; l < got.lines.size(); ++l)
    ASSERT_EQ(got.lines[l].beta, expected.lines[l].beta) << "line " << l;
  for (std::size_t i = 0; i < got.size(); ++i) {
    ASSERT_EQ(got.status[i], expected.status[i]) << "point " << i;
    ASSERT_EQ(got.alpha[i], expected.alpha[i]) << "point " << i;
    if (!expected.isValid(i)) continue;
    ASSERT_NEAR(got.points[i].x, expected.points[i].x, kWireResolutionM) << "point " << i;
    ASSERT_NEAR(got.points[i].y, expected.points[i].y, kWireResolutionM) << "point " << i;
    ASSERT_NEAR(got.points[i].z, expected.points[i].z, kWireResolutionM) << "point " << i;
  }
}

// A TCP relay between a console and the server, our own: it can cut the link once after a number
// of bytes towards the console, and limit that direction's throughput.
class TestProxy : public QObject {
 public:
  TestProxy(quint16 target, qint64 cut_after_bytes, double bytes_per_second)
      : target_(target), cut_after_(cut_after_bytes), rate_(bytes_per_second) {
    server_.listen(QHostAddress::LocalHost, 0);
    connect(&server_, &QTcpServer::newConnection, this, [this] { accept(); });
    connect(&pump_, &QTimer::timeout, this, [this] { pumpDown(); });
    pump_.start(kPumpMs);
    clock_.start();
  }
  quint16 port() const { return server_.serverPort(); }
  int cuts() const { return cuts_; }

 private:
  static constexpr int kPumpMs = 5;
  struct Link {
    QTcpSocket* console = nullptr;
    QTcpSocket* robot = nullptr;
    QByteArray down;  // robot -> console, waiting for its turn
  };

  void accept() {
    while (QTcpSocket* console = server_.nextPendingConnection()) {
      auto link = std::make_shared<Link>();
      link->console = console;
      link->robot = new QTcpSocket(this);
      links_.push_back(link);
      connect(console, &QTcpSocket::readyRead, this,
              [link] { link->robot->write(link->console->readAll()); });
      connect(link->robot, &QTcpSocket::readyRead, this, [this, link] {
        link->down += link->robot->readAll();
        pumpDown();
      });
      auto close = [this, link] { drop(link); };
      connect(console, &QTcpSocket::disconnected, this, close);
      connect(link->robot, &QTcpSocket::disconnected, this, close);
      link->robot->connectToHost(QHostAddress::LocalHost, target_);
    }
  }

  void drop(const std::shared_ptr<Link>& link) {
    if (!link->console) return;
    link->console->disconnect(this);
    link->robot->disconnect(this);
    link->console->abort();
    link->robot->abort();
    link->console->deleteLater();
    link->robot->deleteLater();
    link->console = link->robot = nullptr;
  }

  void pumpDown() {
    const double now_s = clock_.elapsed() / 1000.0;
    if (rate_ > 0)
      budget_ = std::min(rate_ * kPumpMs / 1000.0 * 4, budget_ + rate_ * (now_s - last_s_));
    last_s_ = now_s;
    for (const auto& link : links_) {
      if (!link->console || link->down.isEmpty()) continue;
      qint64 n = link->down.size();
      if (rate_ > 0) n = std::min<qint64>(n, qint64(budget_));
      if (cut_after_ > 0 && cuts_ == 0) n = std::min(n, cut_after_ - forwarded_);
      if (n > 0) {
        link->console->write(link->down.left(n));
        link->down.remove(0, int(n));
        forwarded_ += n;
        budget_ -= double(n);
      }
      if (cut_after_ > 0 && cuts_ == 0 && forwarded_ >= cut_after_) {
        ++cuts_;  // the tether is cut: both ends see the connection die
        drop(link);
      }
    }
  }

  QTcpServer server_;
  QTimer pump_;
  QElapsedTimer clock_;
  quint16 target_;
  qint64 cut_after_;
  double rate_;
  double budget_ = 0;
  double last_s_ = 0;
  qint64 forwarded_ = 0;
  int cuts_ = 0;
  std::vector<std::shared_ptr<Link>> links_;
};

class RemoteLink : public ::testing::Test {
 protected:
  void SetUp() override {
    application();
    ASSERT_TRUE(credentials_dir_.isValid());
    initCredentials(credentials_dir_.path());
    device_ = std::make_unique<SimulatedRosi>(*sim::builtinScene("garage"));
    device_->setSpeedup(50.0);
    ServerOptions options;
    options.storage_dir = QDir(storage_.path()).filePath("robot-scans");
    server_ = std::make_unique<RemoteScanServer>(
        device_.get(), loadRobotCredentials(credentials_dir_.path()), options);
    connect(server_.get(), &RemoteScanServer::logMessage,
            [this](const QString& line) { log_ << line; });
    ASSERT_TRUE(server_->listen(QHostAddress::LocalHost, 0));
    device_->connectDevice();
  }

  static void connect(auto* sender, auto signal, auto slot) {
    QObject::connect(sender, signal, slot);
  }

  RemoteOptions consoleOptions(quint16 port) const {
    RemoteOptions options;
    options.port = port;
    options.credentials = loadConsoleCredentials(credentials_dir_.path());
    options.ping_interval_ms = 200;
    options.reconnect_delay_ms = 100;
    return options;
  }

  struct Result {
    std::shared_ptr<const Scan> scan;
    bool complete = false;
    bool done = false;
    QStringList failures;
  };
  static void collect(RemoteRosi& rosi, Result& result) {
    connect(&rosi, &RemoteRosi::scanFinished, [&result](std::shared_ptr<const Scan> scan, bool c) {
      result.scan = std::move(scan);
      result.complete = c;
      result.done = true;
    });
    connect(&rosi, &RemoteRosi::failed,
            [&result](const QString& reason) { result.failures << reason; });
  }

  bool logMentions(const QString& text) const {
    for (const QString& line : log_)
      if (line.contains(text)) return true;
    return false;
  }

  QTemporaryDir credentials_dir_, storage_;
  std::unique_ptr<SimulatedRosi> device_;
  std::unique_ptr<RemoteScanServer> server_;
  QStringList log_;
};

TEST_F(RemoteLink, ScanEndToEndEqualsTheSimulatorsScanAndTheRobotsFile) {
  RemoteRosi rosi(consoleOptions(server_->serverPort()));
  Result result;
  collect(rosi, result);
  QString saved;
  connect(server_.get(), &RemoteScanServer::scanSaved,
          [&saved](const QString& path, bool) { saved = path; });
  rosi.connectDevice();
  ASSERT_TRUE(waitFor([&] { return rosi.state() == ScannerDevice::State::kIdle; }));
  EXPECT_EQ(rosi.role(), Role::kControl);
  rosi.startScan({kGarageLines, 0.0});
  ASSERT_TRUE(waitFor([&] { return result.done; }));
  ASSERT_TRUE(result.complete) << result.failures.join("; ").toStdString();
  const Scan expected = simulatorScan(kGarageLines);
  expectSameScan(*result.scan, expected);
  ASSERT_TRUE(result.scan->sensor_pose.has_value());  // the scan's pose came with it
  EXPECT_EQ(result.scan->sensor_pose->position, expected.sensor_pose->position);
  EXPECT_EQ(result.scan->sensor_pose->rotation, expected.sensor_pose->rotation);
  // The robot saved it before calling it finished, and that file is what the console got.
  ASSERT_FALSE(saved.isEmpty());
  LoadOptions load;
  load.self_hit_radius = 0.0;
  const Scan on_robot = loadScan(saved.toStdString(), load);
  ASSERT_EQ(on_robot.size(), result.scan->size());
  for (std::size_t i = 0; i < on_robot.size(); ++i) {
    ASSERT_EQ(on_robot.isValid(i), result.scan->isValid(i)) << i;
    if (on_robot.isValid(i)) {
      ASSERT_EQ(on_robot.points[i].x, result.scan->points[i].x) << i;
    }
  }
  std::cout << "[ figure ] bytes received for the 76,140-point scan: "
            << rosi.linkStatistics().bytes_received << " (TLS included)\n";
  EXPECT_LT(rosi.linkStatistics().bytes_received, 1'000'000);
  EXPECT_TRUE(rosi.linkStatus().contains("connected")) << rosi.linkStatus().toStdString();
}

TEST_F(RemoteLink, ALinkCutMidScanIsResumedWithNothingLostOrDuplicated) {
  // Real-time-ish scanning so the cut happens while the robot is still scanning.
  device_->setSpeedup(4.0);
  TestProxy proxy(server_->serverPort(), /*cut_after_bytes=*/120'000, /*bytes_per_second=*/0);
  RemoteRosi rosi(consoleOptions(proxy.port()));
  Result result;
  collect(rosi, result);
  bool saw_lost = false;
  connect(&rosi, &RemoteRosi::linkStatusChanged,
          [&saw_lost](const QString& words) { saw_lost |= words.contains("link lost"); });
  bool robot_saved_complete = false;
  connect(server_.get(), &RemoteScanServer::scanSaved,
          [&](const QString&, bool complete) { robot_saved_complete = complete; });
  rosi.connectDevice();
  ASSERT_TRUE(waitFor([&] { return rosi.state() == ScannerDevice::State::kIdle; }));
  rosi.startScan({kGarageLines, 0.0});
  ASSERT_TRUE(waitFor([&] { return result.done; }));
  EXPECT_TRUE(robot_saved_complete);  // the robot kept scanning and saved it whole
  EXPECT_EQ(proxy.cuts(), 1);
  EXPECT_TRUE(saw_lost);
  EXPECT_GE(rosi.linkStatistics().reconnections, 1);
  ASSERT_TRUE(result.complete) << result.failures.join("; ").toStdString();
  expectSameScan(*result.scan, simulatorScan(kGarageLines));
  EXPECT_TRUE(logMentions("resumes scan")) << log_.join("\n").toStdString();
  std::cout << "[ figure ] after the cut: " << rosi.linkStatistics().reconnections
            << " reconnection(s), " << rosi.linkStatistics().duplicate_lines_dropped
            << " repeated lines dropped\n";
}

TEST_F(RemoteLink, AScanFinishedWhileTheLinkWasDownArrivesWhole) {
  // The cut comes early and reconnection is slow: the robot finishes and saves the scan alone.
  device_->setSpeedup(50.0);
  TestProxy proxy(server_->serverPort(), /*cut_after_bytes=*/30'000, 0);
  RemoteOptions options = consoleOptions(proxy.port());
  options.reconnect_delay_ms = 1500;
  RemoteRosi rosi(options);
  Result result;
  collect(rosi, result);
  bool robot_finished = false;
  connect(server_.get(), &RemoteScanServer::scanSaved,
          [&](const QString&, bool complete) { robot_finished = complete; });
  int robot_finished_while_lost = 0;
  connect(&rosi, &RemoteRosi::linkStatusChanged, [&](const QString& words) {
    if (words.contains("link lost") && robot_finished) robot_finished_while_lost = 1;
  });
  rosi.connectDevice();
  ASSERT_TRUE(waitFor([&] { return rosi.state() == ScannerDevice::State::kIdle; }));
  rosi.startScan({kGarageLines, 0.0});
  ASSERT_TRUE(waitFor([&] { return result.done; }));
  EXPECT_EQ(robot_finished_while_lost, 1);
  ASSERT_TRUE(result.complete) << result.failures.join("; ").toStdString();
  expectSameScan(*result.scan, simulatorScan(kGarageLines));
}

TEST_F(RemoteLink, OneMegabitLinkTimeFromLastLineToResult) {
  // The RoSi at its real line rate (37.5 lines/s) behind a 1 Mbit/s link; reported, not asserted.
  device_->setSpeedup(1.0);
  TestProxy proxy(server_->serverPort(), 0, /*bytes_per_second=*/1e6 / 8);
  RemoteRosi rosi(consoleOptions(proxy.port()));
  Result result;
  collect(rosi, result);
  QElapsedTimer clock;
  clock.start();
  qint64 last_line_ms = -1, result_ms = -1;
  connect(device_.get(), &ScannerDevice::scanFinished,
          [&](auto, bool) { last_line_ms = clock.elapsed(); });
  connect(&rosi, &RemoteRosi::scanFinished, [&](auto, bool) { result_ms = clock.elapsed(); });
  rosi.connectDevice();
  ASSERT_TRUE(waitFor([&] { return rosi.state() == ScannerDevice::State::kIdle; }));
  rosi.startScan({kGarageLines, 0.0});
  ASSERT_TRUE(waitFor([&] { return result.done; }));
  ASSERT_TRUE(result.complete);
  expectSameScan(*result.scan, simulatorScan(kGarageLines));
  std::cout << "[ figure ] 1 Mbit/s link, " << kGarageLines
            << " lines at 37.5 lines/s: last line on the robot -> complete scan on the console: "
            << (result_ms - last_line_ms) << " ms (scan took " << last_line_ms << " ms)\n";
}

TEST_F(RemoteLink, CancelKeepsWhatArrivedOnBothSidesMarkedPartial) {
  device_->setSpeedup(2.0);  // 75 lines/s: slow enough to cancel halfway
  RemoteRosi rosi(consoleOptions(server_->serverPort()));
  Result result;
  collect(rosi, result);
  QString saved;
  connect(server_.get(), &RemoteScanServer::scanSaved,
          [&saved](const QString& path, bool) { saved = path; });
  int received = 0;
  connect(&rosi, &RemoteRosi::progress, [&received](int lines, int) { received = lines; });
  rosi.connectDevice();
  ASSERT_TRUE(waitFor([&] { return rosi.state() == ScannerDevice::State::kIdle; }));
  rosi.startScan({kGarageLines, 0.0});
  ASSERT_TRUE(waitFor([&] { return received >= 40; }));
  rosi.cancelScan();
  ASSERT_TRUE(waitFor([&] { return result.done; }));
  EXPECT_FALSE(result.complete);
  EXPECT_GE(result.scan->lines.size(), 40U);
  EXPECT_LT(result.scan->lines.size(), std::size_t(kGarageLines));
  EXPECT_TRUE(saved.endsWith("-partial.pcd")) << saved.toStdString();
  EXPECT_EQ(rosi.state(), ScannerDevice::State::kIdle);
}

TEST_F(RemoteLink, RefusedWithoutCredentials) {
  // A client that does not speak TLS at all: its Hello never reaches the protocol.
  QTcpSocket plain;
  plain.connectToHost(QHostAddress::LocalHost, server_->serverPort());
  ASSERT_TRUE(waitFor([&] { return plain.state() == QAbstractSocket::ConnectedState; }));
  plain.write(encodeFrame(encode(Hello{})));
  ASSERT_TRUE(waitFor([&] { return plain.state() == QAbstractSocket::UnconnectedState; }));
  EXPECT_TRUE(logMentions("TLS handshake failed")) << log_.join("\n").toStdString();
  EXPECT_EQ(server_->statistics().connections_refused, 1);
}

TEST_F(RemoteLink, RefusedWithWrongCredentialsWithAReasonOnBothSides) {
  QTemporaryDir other;
  initCredentials(other.path());
  RemoteOptions options = consoleOptions(server_->serverPort());
  options.credentials = loadConsoleCredentials(other.path());  // same identity, another key
  RemoteRosi rosi(options);
  Result result;
  collect(rosi, result);
  rosi.connectDevice();
  ASSERT_TRUE(waitFor([&] { return rosi.state() == ScannerDevice::State::kFailed; }));
  ASSERT_FALSE(result.failures.isEmpty());
  EXPECT_TRUE(result.failures.front().contains("credentials"))
      << result.failures.front().toStdString();
  EXPECT_TRUE(logMentions("TLS handshake failed")) << log_.join("\n").toStdString();

  options.credentials.key.identity = "intruder";  // an identity the robot does not know
  RemoteRosi stranger(options);
  stranger.connectDevice();
  ASSERT_TRUE(waitFor([&] { return stranger.state() == ScannerDevice::State::kFailed; }));
  EXPECT_TRUE(logMentions("unknown console identity")) << log_.join("\n").toStdString();
}

TEST_F(RemoteLink, ASecondControllingConsoleMayOnlyWatch) {
  RemoteRosi first(consoleOptions(server_->serverPort()));
  RemoteRosi second(consoleOptions(server_->serverPort()));
  Result first_result, second_result;
  collect(first, first_result);
  collect(second, second_result);
  QString note;
  connect(&second, &RemoteRosi::notice, [&note](const QString& text) { note = text; });
  first.connectDevice();
  ASSERT_TRUE(waitFor([&] { return first.state() == ScannerDevice::State::kIdle; }));
  second.connectDevice();
  ASSERT_TRUE(waitFor([&] { return second.state() == ScannerDevice::State::kIdle; }));
  EXPECT_EQ(first.role(), Role::kControl);
  EXPECT_EQ(second.role(), Role::kWatch);
  EXPECT_TRUE(note.contains("controls the scanner")) << note.toStdString();
  // The watcher cannot start a scan...
  second.startScan({50, 0.0});
  ASSERT_TRUE(waitFor([&] { return !second_result.failures.isEmpty(); }));
  EXPECT_TRUE(second_result.failures.front().contains("watching"));
  EXPECT_EQ(second.state(), ScannerDevice::State::kIdle);
  // ...but sees the controller's scan arrive, whole.
  first.startScan({kGarageLines, 0.0});
  ASSERT_TRUE(waitFor([&] { return first_result.done && second_result.done; }));
  ASSERT_TRUE(first_result.complete);
  ASSERT_TRUE(second_result.complete);
  expectSameScan(*second_result.scan, *first_result.scan);
}

// A TLS client with the right key that speaks whatever frames the test gives it.
class RawTlsClient {
 public:
  RawTlsClient(quint16 port, const ConsoleCredentials& credentials) {
    configurePskTls(socket_);
    QObject::connect(&socket_, &QSslSocket::preSharedKeyAuthenticationRequired,
                     [credentials](QSslPreSharedKeyAuthenticator* a) {
                       a->setIdentity(credentials.key.identity);
                       a->setPreSharedKey(credentials.key.key);
                     });
    QObject::connect(&socket_, &QSslSocket::readyRead, [this] { received_ += socket_.readAll(); });
    socket_.connectToHostEncrypted("127.0.0.1", port);
  }
  QSslSocket& socket() { return socket_; }
  QByteArray& received() { return received_; }

 private:
  QSslSocket socket_;
  QByteArray received_;
};

TEST_F(RemoteLink, AnOldProtocolVersionIsRefusedWithTheReason) {
  RawTlsClient client(server_->serverPort(), loadConsoleCredentials(credentials_dir_.path()));
  ASSERT_TRUE(waitFor([&] { return client.socket().isEncrypted(); }));
  Frame hello = encode(Hello{});
  hello.version = 0;
  client.socket().write(encodeFrame(hello));
  ASSERT_TRUE(
      waitFor([&] { return client.socket().state() == QAbstractSocket::UnconnectedState; }));
  FrameParser parser;
  parser.feed(client.received());
  const std::optional<Frame> answer = parser.next();
  ASSERT_TRUE(answer.has_value());
  ASSERT_EQ(answer->type, MessageType::kRefused);
  const QString reason = decodeText(*answer);
  EXPECT_TRUE(reason.contains("protocol version 0")) << reason.toStdString();
  EXPECT_TRUE(logMentions("protocol version 0"));
}

TEST_F(RemoteLink, TheSameConsoleReconnectingTakesItsControlBack) {
  // Over a dead link the robot may not yet know the old connection is gone: the console's session
  // token lets its new connection take control, and the old one is closed.
  const ConsoleCredentials credentials = loadConsoleCredentials(credentials_dir_.path());
  const QByteArray token(kSessionTokenBytes, 'A');
  auto welcomeOf = [](RawTlsClient& client) -> std::optional<Welcome> {
    FrameParser parser;
    parser.feed(client.received());
    const std::optional<Frame> frame = parser.next();
    if (!frame || frame->type != MessageType::kWelcome) return std::nullopt;
    return decodeWelcome(*frame);
  };
  RawTlsClient old_link(server_->serverPort(), credentials);
  ASSERT_TRUE(waitFor([&] { return old_link.socket().isEncrypted(); }));
  old_link.socket().write(encodeFrame(encode(Hello{Role::kControl, token, "console"})));
  ASSERT_TRUE(waitFor([&] { return welcomeOf(old_link).has_value(); }));
  EXPECT_EQ(welcomeOf(old_link)->granted, Role::kControl);

  RawTlsClient other(server_->serverPort(), credentials);  // another console: watches
  ASSERT_TRUE(waitFor([&] { return other.socket().isEncrypted(); }));
  other.socket().write(
      encodeFrame(encode(Hello{Role::kControl, QByteArray(kSessionTokenBytes, 'B'), "other"})));
  ASSERT_TRUE(waitFor([&] { return welcomeOf(other).has_value(); }));
  EXPECT_EQ(welcomeOf(other)->granted, Role::kWatch);

  RawTlsClient new_link(server_->serverPort(), credentials);
  ASSERT_TRUE(waitFor([&] { return new_link.socket().isEncrypted(); }));
  new_link.socket().write(encodeFrame(encode(Hello{Role::kControl, token, "console"})));
  ASSERT_TRUE(waitFor([&] { return welcomeOf(new_link).has_value(); }));
  EXPECT_EQ(welcomeOf(new_link)->granted, Role::kControl);
  EXPECT_TRUE(
      waitFor([&] { return old_link.socket().state() == QAbstractSocket::UnconnectedState; }));
  EXPECT_TRUE(logMentions("replaced by a reconnection of the same console"));
}

// One malformed or truncated frame, of the kinds a broken or hostile peer sends.
QByteArray fuzzFrame(QRandomGenerator& random, const Scan& scan) {
  const Frame good = [&] {
    switch (random.bounded(5)) {
      case 0:
        return encode(Hello{});
      case 1:
        return encode(StartScan{10, 0.0});
      case 2:
        return encode(Resume{1, 0});
      case 3:
        return encodeStamp(MessageType::kPing, 1);
      default:
        return encode(Lines{1, 0, encodeScanLines(scan, 0, 1)});
    }
  }();
  QByteArray bytes = encodeFrame(good);
  switch (random.bounded(7)) {
    case 0:  // an absurd length
      qToBigEndian(quint32(random.bounded(quint32(kMaxFrameBytes + 1), quint32(0x7FFFFFFF))),
                   reinterpret_cast<uchar*>(bytes.data()));
      break;
    case 1:  // a wrong version
      bytes[5] = char(2 + random.bounded(200));
      break;
    case 2:  // an unknown type
      bytes[6] = char(23 + random.bounded(200));
      break;
    case 3:  // truncated, then the peer goes away
      bytes.truncate(random.bounded(1, int(bytes.size())));
      break;
    case 4: {  // random payload bytes under a valid header
      for (int i = 7; i < bytes.size(); ++i)
        if (random.bounded(4) == 0) bytes[i] = char(random.bounded(256));
      bytes[6] = char(MessageType::kLines);
      break;
    }
    case 5:  // a message only the robot sends
      bytes = encodeFrame(encode(Welcome{}));
      break;
    default: {  // a length too short for its message
      const quint32 length = quint32(kFrameHeaderBytes + random.bounded(3));
      qToBigEndian(length, reinterpret_cast<uchar*>(bytes.data()));
      bytes.truncate(kLengthBytes + int(length));
      break;
    }
  }
  return bytes;
}

TEST_F(RemoteLink, TenThousandMalformedFramesWhileAGoodConsoleIsServed) {
  constexpr int kFrames = 10000;
  constexpr int kParallel = 16;  // fuzzing connections open at a time
  const ConsoleCredentials credentials = loadConsoleCredentials(credentials_dir_.path());
  const Scan small = simulatorScan(20);
  QRandomGenerator random(20261122);

  RemoteRosi good(consoleOptions(server_->serverPort()));
  Result result;
  int scans_complete = 0;
  connect(&good, &RemoteRosi::scanFinished, [&](std::shared_ptr<const Scan> scan, bool complete) {
    if (complete && scan->lines.size() == 100) ++scans_complete;
    result.done = true;
    result.complete = complete;
  });
  good.connectDevice();
  ASSERT_TRUE(waitFor([&] { return good.state() == ScannerDevice::State::kIdle; }));
  device_->setSpeedup(5.0);

  int sent = 0, closed_by_server = 0, live = 0;
  std::function<void()> launch = [&] {
    if (sent >= kFrames) return;
    ++sent;
    ++live;
    auto* client = new RawTlsClient(server_->serverPort(), credentials);
    QSslSocket* socket = &client->socket();
    const QByteArray frame = fuzzFrame(random, small);
    // Sometimes the bad frame comes first, sometimes after a proper Hello.
    const bool hello_first = random.bounded(2) == 0;
    QObject::connect(socket, &QSslSocket::encrypted, [socket, frame, hello_first] {
      if (hello_first) socket->write(encodeFrame(encode(Hello{Role::kWatch, {}, "fuzzer"})));
      socket->write(frame);
      if (frame.size() < 7 ||
          qFromBigEndian<quint32>(frame.constData()) + 4 > quint32(frame.size()))
        socket->disconnectFromHost();  // truncated: the peer goes away mid-frame
    });
    QObject::connect(socket, &QAbstractSocket::disconnected, [&, client] {
      ++closed_by_server;
      --live;
      client->socket().disconnect();
      QTimer::singleShot(0, [client] { delete client; });
      launch();
    });
  };
  for (int i = 0; i < kParallel; ++i)
    launch();
  // The good console scans again and again while the fuzzer runs.
  int scans_started = 0;
  ASSERT_TRUE(waitFor(
      [&] {
        if (good.state() == ScannerDevice::State::kIdle && scans_started == scans_complete) {
          ++scans_started;
          result.done = false;
          good.startScan({100, 0.0});
        }
        return sent >= kFrames && live == 0;
      },
      600000));
  ASSERT_TRUE(waitFor([&] { return good.state() == ScannerDevice::State::kIdle; }));
  EXPECT_EQ(sent, kFrames);
  EXPECT_EQ(closed_by_server, kFrames);
  EXPECT_GE(scans_complete, 1);
  EXPECT_EQ(good.state(), ScannerDevice::State::kIdle);
  EXPECT_EQ(good.linkStatistics().reconnections, 0);  // the good console was never dropped
  std::cout << "[ figure ] " << kFrames << " malformed frames, " << scans_complete
            << " complete scans served meanwhile; server refused "
            << server_->statistics().connections_refused << " connections\n";
  // Every fuzzing connection is gone; only the good console remains.
  ASSERT_TRUE(waitFor([&] { return server_->connectionCount() == 1; }, 5000));
}

}  // namespace
}  // namespace clearway::hardware::remote

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
