#pragma once

// Shared by the remote protocol's loopback tests: an event loop, bounded waits, the simulator's
// scan to compare with, a server on 127.0.0.1 with a simulated RoSi, and a raw TLS client.

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

constexpr int kGarageLines = 423;  // 76,140 points
constexpr double kWireResolutionM = 0.0005 + 1e-6;
constexpr int kWaitMs = 60000;  // a hung test fails after this instead of hanging

inline QCoreApplication* application() {
  static int argc = 1;
  static char name[] = "hardware_remote_tests";
  static char* argv[] = {name, nullptr};
  static auto* app = new QCoreApplication(argc, argv);
  return app;
}

// Runs the event loop until `done` or `timeout_ms`; returns done().
inline bool waitFor(const std::function<bool()>& done, int timeout_ms = kWaitMs) {
  QElapsedTimer clock;
  clock.start();
  while (!done() && clock.elapsed() < timeout_ms)
    QCoreApplication::processEvents(QEventLoop::AllEvents | QEventLoop::WaitForMoreEvents, 10);
  return done();
}

inline Scan simulatorScan(int lines) {
  sim::SensorModel sensor;
  sensor.lines = lines;
  const sim::Scene scene = *sim::builtinScene("garage");
  return sim::simulateRosi(scene, sensor, sim::defaultPlacement(scene)).scan;
}

// Point for point: same lines, betas, statuses and alphas; coordinates to the wire's 1 mm.
inline void expectSameScan(const Scan& got, const Scan& expected) {
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

}  // namespace clearway::hardware::remote
