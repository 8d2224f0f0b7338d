// `serve` and the remote RoSi over loopback only (127.0.0.1): a scan end to end equal to the
// simulator's, a link cut mid-scan and resumed, a 1 Mbit/s link, cancel, and refusals (no
// credentials, wrong credentials, a second controlling console, an old protocol version). Waits
// are bounded in time (to avoid hangs, never as assertions on speed).

#include <deque>
#include <utility>

#include "remote_test_support.h"

namespace clearway::hardware::remote {
namespace {

// A TCP relay between a console and the server, our own: it can cut the link once after a number
// of bytes towards the console, limit that direction's throughput, and delay what the console
// sends by `up_delay_ms`.
class TestProxy : public QObject {
 public:
  TestProxy(quint16 target, qint64 cut_after_bytes, double bytes_per_second, int up_delay_ms = 0)
      : target_(target),
        cut_after_(cut_after_bytes),
        rate_(bytes_per_second),
        up_delay_ms_(up_delay_ms) {
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
    QByteArray down;                               // robot -> console, waiting for its turn
    std::deque<std::pair<qint64, QByteArray>> up;  // console -> robot, with the time it is due
  };

  void accept() {
    while (QTcpSocket* console = server_.nextPendingConnection()) {
      auto link = std::make_shared<Link>();
      link->console = console;
      link->robot = new QTcpSocket(this);
      links_.push_back(link);
      connect(console, &QTcpSocket::readyRead, this, [this, link] {
        link->up.emplace_back(clock_.elapsed() + up_delay_ms_, link->console->readAll());
        pumpDown();
      });
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
      while (link->console && !link->up.empty() && link->up.front().first <= clock_.elapsed()) {
        link->robot->write(link->up.front().second);
        link->up.pop_front();
      }
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
  int up_delay_ms_;
  double budget_ = 0;
  double last_s_ = 0;
  qint64 forwarded_ = 0;
  int cuts_ = 0;
  std::vector<std::shared_ptr<Link>> links_;
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
  rosi.startScan({kGarageLines, 0.0, {}});
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
  rosi.startScan({kGarageLines, 0.0, {}});
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
  rosi.startScan({kGarageLines, 0.0, {}});
  ASSERT_TRUE(waitFor([&] { return result.done; }));
  EXPECT_EQ(robot_finished_while_lost, 1);
  ASSERT_TRUE(result.complete) << result.failures.join("; ").toStdString();
  expectSameScan(*result.scan, simulatorScan(kGarageLines));
}

TEST_F(RemoteLink, OneMegabitLinkTimeFromLastLineToResult) {
  // Behind a 1 Mbit/s link: the RoSi at its real line rate (37.5 lines/s), and a robot that has
  // the whole scan at once (the worst case: everything is backlog). Reported, not asserted.
  TestProxy proxy(server_->serverPort(), 0, /*bytes_per_second=*/1e6 / 8);
  for (const double speedup : {1.0, 100.0}) {
    device_->setSpeedup(speedup);
    RemoteRosi rosi(consoleOptions(proxy.port()));
    Result result;
    collect(rosi, result);
    QElapsedTimer clock;
    clock.start();
    qint64 last_line_ms = -1, result_ms = -1;
    QObject context;
    QObject::connect(device_.get(), &ScannerDevice::scanFinished, &context,
                     [&](auto, bool) { last_line_ms = clock.elapsed(); });
    connect(&rosi, &RemoteRosi::scanFinished, [&](auto, bool) { result_ms = clock.elapsed(); });
    rosi.connectDevice();
    ASSERT_TRUE(waitFor([&] { return rosi.state() == ScannerDevice::State::kIdle; }));
    const qint64 start_ms = clock.elapsed();
    rosi.startScan({kGarageLines, 0.0, {}});
    ASSERT_TRUE(waitFor([&] { return result.done; }));
    ASSERT_TRUE(result.complete);
    expectSameScan(*result.scan, simulatorScan(kGarageLines));
    std::cout << "[ figure ] 1 Mbit/s link, " << kGarageLines << " lines, RoSi at x" << speedup
              << " real time: last line on the robot -> complete scan on the "
              << "console: " << (result_ms - last_line_ms) << " ms (acquisition took "
              << (last_line_ms - start_ms) << " ms)\n";
    rosi.disconnectDevice();
  }
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
  rosi.startScan({kGarageLines, 0.0, {}});
  ASSERT_TRUE(waitFor([&] { return received >= 40; }));
  rosi.cancelScan();
  ASSERT_TRUE(waitFor([&] { return result.done; }));
  EXPECT_FALSE(result.complete);
  EXPECT_GE(result.scan->lines.size(), 40U);
  EXPECT_LT(result.scan->lines.size(), std::size_t(kGarageLines));
  EXPECT_TRUE(saved.endsWith("-partial.pcd")) << saved.toStdString();
  EXPECT_EQ(rosi.state(), ScannerDevice::State::kIdle);
}

TEST_F(RemoteLink, DisconnectingMidScanKeepsWhatArrivedAndTheRobotItsCopy) {
  device_->setSpeedup(2.0);
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
  rosi.startScan({kGarageLines, 0.0, {}});
  ASSERT_TRUE(waitFor([&] { return received >= 40; }));
  rosi.disconnectDevice();
  ASSERT_TRUE(result.done);  // handed over at once, marked incomplete
  EXPECT_FALSE(result.complete);
  EXPECT_GE(result.scan->lines.size(), 40U);
  // The pose came before the lines (the robot's ScanStarted repeated with it): the partial scan
  // is judged from where it was taken, not as a scan without pose.
  const Scan expected = simulatorScan(kGarageLines);
  ASSERT_TRUE(expected.sensor_pose.has_value());
  ASSERT_TRUE(result.scan->sensor_pose.has_value());
  EXPECT_EQ(result.scan->sensor_pose->position, expected.sensor_pose->position);
  EXPECT_EQ(result.scan->sensor_pose->rotation, expected.sensor_pose->rotation);
  EXPECT_EQ(rosi.state(), ScannerDevice::State::kDisconnected);
  ASSERT_TRUE(waitFor([&] { return !saved.isEmpty(); }));  // the robot saved its copy
}

TEST_F(RemoteLink, WhileTheRobotIsGoneTheConsoleSaysSoAndStartsNothing) {
  RemoteRosi rosi(consoleOptions(server_->serverPort()));
  Result result;
  collect(rosi, result);
  rosi.connectDevice();
  ASSERT_TRUE(waitFor([&] { return rosi.state() == ScannerDevice::State::kIdle; }));
  server_.reset();  // the robot's server goes away
  ASSERT_TRUE(waitFor([&] { return rosi.linkStatus().contains("link lost"); }));
  EXPECT_TRUE(rosi.linkStatus().contains("reconnecting")) << rosi.linkStatus().toStdString();
  rosi.startScan({50, 0.0, {}});
  ASSERT_FALSE(result.failures.isEmpty());
  EXPECT_TRUE(result.failures.last().contains("link to the robot is down"));
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
  second.startScan({50, 0.0, {}});
  ASSERT_TRUE(waitFor([&] { return !second_result.failures.isEmpty(); }));
  EXPECT_TRUE(second_result.failures.front().contains("watching"));
  EXPECT_EQ(second.state(), ScannerDevice::State::kIdle);
  // ...but sees the controller's scan arrive, whole.
  first.startScan({kGarageLines, 0.0, {}});
  ASSERT_TRUE(waitFor([&] { return first_result.done && second_result.done; }));
  ASSERT_TRUE(first_result.complete);
  ASSERT_TRUE(second_result.complete);
  expectSameScan(*second_result.scan, *first_result.scan);
}

// A watcher that connects while a scan runs receives that scan, from its first line (it waited,
// silent, for a ScanStarted that had gone by, and never heard of that scan or its end). Its link
// delays what it sends, so the robot streams lines before it reads the watcher's Resume: those
// are no protocol error, and nothing is lost or taken twice.
TEST_F(RemoteLink, AWatcherArrivingDuringAScanReceivesItFromItsFirstLine) {
  device_->setSpeedup(1.0);  // real time, 37.5 lines/s: the scan runs for 11 s
  RemoteRosi controller(consoleOptions(server_->serverPort()));
  Result controller_result, watcher_result;
  collect(controller, controller_result);
  int received = 0;
  connect(&controller, &RemoteRosi::progress, [&received](int lines, int) { received = lines; });
  controller.connectDevice();
  ASSERT_TRUE(waitFor([&] { return controller.state() == ScannerDevice::State::kIdle; }));
  controller.startScan({kGarageLines, 0.0, {}});
  ASSERT_TRUE(waitFor([&] { return received >= 40; }));

  TestProxy slow_uplink(server_->serverPort(), 0, 0, /*up_delay_ms=*/400);
  RemoteOptions options = consoleOptions(slow_uplink.port());
  options.role = Role::kWatch;
  RemoteRosi watcher(options);
  collect(watcher, watcher_result);
  QStringList notices;
  connect(&watcher, &RemoteRosi::notice, [&notices](const QString& text) { notices << text; });
  watcher.connectDevice();
  ASSERT_TRUE(waitFor([&] { return controller_result.done && watcher_result.done; }));
  ASSERT_TRUE(controller_result.complete) << controller_result.failures.join("; ").toStdString();
  EXPECT_TRUE(watcher_result.failures.isEmpty())
      << watcher_result.failures.join("; ").toStdString();
  EXPECT_TRUE(notices.join("\n").contains("under way")) << notices.join("\n").toStdString();
  EXPECT_EQ(watcher.linkStatistics().reconnections, 0);
  ASSERT_TRUE(watcher_result.complete);
  expectSameScan(*watcher_result.scan, *controller_result.scan);
  ASSERT_TRUE(watcher_result.scan->sensor_pose.has_value());
  EXPECT_EQ(watcher_result.scan->sensor_pose->position,
            controller_result.scan->sensor_pose->position);
  EXPECT_TRUE(logMentions("resumes scan")) << log_.join("\n").toStdString();
}

// Why a first connection failed, in words: it was always "the credentials may be wrong".
TEST_F(RemoteLink, AFailedFirstConnectionSaysWhatIsAtTheOtherEnd) {
  auto failureOf = [this](RemoteOptions options) {
    RemoteRosi rosi(options);
    Result result;
    collect(rosi, result);
    rosi.connectDevice();
    waitFor([&] { return rosi.state() == ScannerDevice::State::kFailed; });
    return result.failures.join("; ");
  };
  // Nothing listens at the port.
  quint16 closed_port = 0;
  {
    QTcpServer gone;
    ASSERT_TRUE(gone.listen(QHostAddress::LocalHost, 0));
    closed_port = gone.serverPort();
  }
  const QString nothing = failureOf(consoleOptions(closed_port));
  EXPECT_TRUE(nothing.contains(QString("nothing listens at 127.0.0.1:%1").arg(closed_port)))
      << nothing.toStdString();
  EXPECT_FALSE(nothing.contains("credentials")) << nothing.toStdString();
  // No such host.
  RemoteOptions unknown = consoleOptions(47100);
  unknown.host = "no-such-robot.invalid";
  const QString no_host = failureOf(unknown);
  EXPECT_TRUE(no_host.contains("no-such-robot.invalid:47100: host not found"))
      << no_host.toStdString();
  EXPECT_FALSE(no_host.contains("credentials")) << no_host.toStdString();
  // A web server: it answers, but not TLS with a pre-shared key.
  QTcpServer web;
  ASSERT_TRUE(web.listen(QHostAddress::LocalHost, 0));
  QObject::connect(&web, &QTcpServer::newConnection, [&web] {
    while (QTcpSocket* peer = web.nextPendingConnection()) {
      QObject::connect(peer, &QTcpSocket::readyRead, [peer] {
        peer->readAll();
        peer->write("HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\n\r\n");
        peer->disconnectFromHost();
      });
    }
  });
  const QString http = failureOf(consoleOptions(web.serverPort()));
  EXPECT_TRUE(http.contains(QString("127.0.0.1:%1 does not speak Clearway's protocol (not a "
                                    "Clearway robot?)")
                                .arg(web.serverPort())))
      << http.toStdString();
  EXPECT_FALSE(http.contains("credentials")) << http.toStdString();
  // A server that takes the connection and says nothing.
  QTcpServer silent;
  ASSERT_TRUE(silent.listen(QHostAddress::LocalHost, 0));
  RemoteOptions quiet = consoleOptions(silent.serverPort());
  quiet.connect_timeout_ms = 1000;
  const QString mute = failureOf(quiet);
  EXPECT_TRUE(mute.contains("does not speak Clearway's protocol")) << mute.toStdString();
  EXPECT_FALSE(mute.contains("credentials")) << mute.toStdString();
  // The robot itself, with a key it does not know: the credentials are named.
  QTemporaryDir other;
  initCredentials(other.path());
  RemoteOptions wrong_key = consoleOptions(server_->serverPort());
  wrong_key.credentials = loadConsoleCredentials(other.path());
  const QString refused = failureOf(wrong_key);
  EXPECT_TRUE(refused.contains("credentials may be wrong")) << refused.toStdString();
  EXPECT_FALSE(refused.contains("does not speak")) << refused.toStdString();
}

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

// A console resuming a scan the robot no longer holds (it restarted) is told where the robot saved
// it, or that it has no file of it; it was told "it keeps the last 4", which was not why.
TEST_F(RemoteLink, ResumingAScanTheRobotNoLongerHoldsSaysWhereItsFileIs) {
  const QString storage = QDir(storage_.path()).filePath("robot-scans");
  ASSERT_TRUE(QDir().mkpath(storage));
  QFile saved(QDir(storage).filePath("scan-4242-partial.pcd"));
  ASSERT_TRUE(saved.open(QIODevice::WriteOnly));
  saved.close();
  auto answerTo = [&](std::uint64_t scan_id) -> std::optional<ScanFinished> {
    RawTlsClient client(server_->serverPort(), loadConsoleCredentials(credentials_dir_.path()));
    if (!waitFor([&] { return client.socket().isEncrypted(); })) return std::nullopt;
    client.socket().write(encodeFrame(encode(Hello{Role::kWatch, {}, "console"})));
    client.socket().write(encodeFrame(encode(Resume{scan_id, 0})));
    std::optional<ScanFinished> finished;
    waitFor([&] {
      FrameParser parser;
      parser.feed(client.received());
      while (const std::optional<Frame> frame = parser.next())
        if (frame->type == MessageType::kScanFinished) finished = decodeScanFinished(*frame);
      return finished.has_value();
    });
    return finished;
  };
  const std::optional<ScanFinished> kept = answerTo(4242);
  ASSERT_TRUE(kept.has_value());
  EXPECT_FALSE(kept->complete);
  EXPECT_TRUE(kept->reason.contains("scan-4242-partial.pcd")) << kept->reason.toStdString();
  EXPECT_TRUE(kept->saved_as.endsWith("scan-4242-partial.pcd")) << kept->saved_as.toStdString();
  const std::optional<ScanFinished> gone = answerTo(77);
  ASSERT_TRUE(gone.has_value());
  EXPECT_TRUE(gone->reason.contains("has no file of it")) << gone->reason.toStdString();
  EXPECT_TRUE(gone->saved_as.isEmpty());
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

}  // namespace
}  // namespace clearway::hardware::remote
