// clearway-cli serve: the RoSi on the robot, offered to consoles over the remote protocol
// (docs/PROTOCOL.md). Also `serve --init-credentials DIR`, the first-run step.

#include <QCoreApplication>
#include <QDateTime>
#include <QDir>
#include <QStandardPaths>
#include <QTimer>
#include <atomic>
#include <csignal>
#include <iostream>
#include <memory>

#include "arguments.h"
#include "clearway/hardware/remote_server.h"
#include "clearway/hardware/serial_rosi.h"
#include "clearway/hardware/simulated_rosi.h"
#include "clearway/sim/builtin_scenes.h"
#include "clearway/sim/scene_io.h"
#include "commands.h"
#include "host_port.h"
#include "mount_options.h"

namespace clearway::cli {
namespace {

using namespace hardware::remote;

std::atomic<bool> stop_requested{false};
void requestStop(int) {
  stop_requested = true;
}
constexpr int kStopPollMs = 100;  // how often the event loop looks at the signal flag
// Asked to stop during a scan, serve cancels it and waits this long for its lines to be saved.
constexpr int kStopScanMs = 5000;

int initOnly(const std::string& dir) {
  try {
    for (const QString& path : initCredentials(QString::fromStdString(dir)))
      std::cout << "wrote " << path.toStdString() << "\n";
  } catch (const CredentialsError& error) {
    std::cerr << "clearway-cli serve: " << error.what() << "\n";
    return 1;
  }
  std::cout << "Keep robot.json on the robot; copy console.json to the console's computer.\n";
  return 0;
}

std::unique_ptr<hardware::ScannerDevice> makeDevice(const Arguments& arguments) {
  const std::shared_ptr<hardware::PoseSource> pose_source = poseSourceOption(arguments);
  if (const auto scene_name = arguments.option("simulate")) {
    // The simulator scans from its scene's own pose and writes it into every scan.
    if (pose_source)
      throw UsageError("--arm and --mount are for the serial RoSi (--lms, --turntable)");
    std::optional<sim::Scene> scene = sim::builtinScene(*scene_name);
    if (!scene) {
      if (!scene_name->ends_with(".json")) throw UsageError("unknown scene '" + *scene_name + "'");
      scene = sim::loadScene(*scene_name);
    }
    auto device = std::make_unique<hardware::SimulatedRosi>(*scene);
    device->setSpeedup(arguments.number("speed", 1.0, 0.01, 1000.0));
    return device;
  }
  const auto lms = arguments.option("lms"), table = arguments.option("turntable");
  if (!lms || !table)
    throw UsageError("give the devices (--lms PORT --turntable PORT) or --simulate SCENE");
  if (const std::string problem = hardware::checkDistinctPorts(namedPorts(arguments));
      !problem.empty())
    throw UsageError(problem);
  auto device = std::make_unique<hardware::SerialRosi>(
      QString::fromStdString(*lms), QString::fromStdString(*table),
      int(arguments.integer("baud", 38400, 9600, 500000)));
  // Asked before every scan; a scan whose pose cannot be read is not started (it could put a
  // wall on the floor), and the console is told why.
  if (pose_source) device->setPoseSource(pose_source);
  return device;
}

void log(const QString& line) {
  std::cerr << QDateTime::currentDateTime().toString(Qt::ISODateWithMs).toStdString()
            << " serve: " << line.toStdString() << std::endl;
}

}  // namespace

int runServe(const std::vector<std::string>& words) {
  const Arguments arguments(words, {},
                            {"init-credentials", "credentials", "listen", "simulate", "speed",
                             "lms", "turntable", "arm", "mount", "baud", "storage", "seconds"});
  arguments.expectPositional(
      0,
      "clearway-cli serve --credentials DIR --listen HOST:PORT "
      "(--simulate SCENE | --lms PORT --turntable PORT [--arm PORT] [--mount POSE]) "
      "[--storage DIR]");
  if (const auto dir = arguments.option("init-credentials")) return initOnly(*dir);
  const auto credentials_dir = arguments.option("credentials");
  const auto listen = arguments.option("listen");
  if (!credentials_dir || !listen)
    throw UsageError("--credentials DIR and --listen HOST:PORT are required");
  const auto [host, port] = parseHostPort(*listen, true);

  int argc = 1;
  char name[] = "clearway-cli";
  char* argv[] = {name, nullptr};
  QCoreApplication app(argc, argv);

  RobotCredentials credentials;
  try {
    credentials = loadRobotCredentials(QString::fromStdString(*credentials_dir));
  } catch (const CredentialsError& error) {
    std::cerr << "clearway-cli serve: " << error.what() << "\n";
    return 1;
  }
  ServerOptions options;
  options.storage_dir =
      arguments.option("storage")
          ? QString::fromStdString(*arguments.option("storage"))
          : QDir(QStandardPaths::writableLocation(QStandardPaths::GenericDataLocation))
                .filePath("clearway/robot-scans");
  std::unique_ptr<hardware::ScannerDevice> device = makeDevice(arguments);
  RemoteScanServer server(device.get(), credentials, options);
  QObject::connect(&server, &RemoteScanServer::logMessage, &log);
  server.recoverInterruptedScans();  // before any console can ask for them

  const QHostAddress address =
      host == "localhost" ? QHostAddress(QHostAddress::LocalHost) : QHostAddress(host);
  if (address.isNull()) throw UsageError("'" + host.toStdString() + "' is not an IP address");
  if (!server.listen(address, port)) {
    std::cerr << "clearway-cli serve: cannot listen on " << *listen << ": "
              << server.errorString().toStdString() << "\n";
    return 1;
  }
  QObject::connect(device.get(), &hardware::ScannerDevice::failed, &log);
  device->connectDevice();
  // Tests and scripts read the port from this line (with --listen HOST:0 the system picks it).
  std::cout << "listening on " << server.serverAddress().toString().toStdString() << ":"
            << server.serverPort() << " (" << device->description().toStdString()
            << "), saving scans in " << options.storage_dir.toStdString() << std::endl;

  std::signal(SIGINT, requestStop);
  std::signal(SIGTERM, requestStop);
  const double seconds = arguments.number("seconds", 0.0, 0.0, 1e7);  // 0 = until interrupted
  // Stopping (a signal, or --seconds) during a scan: the scan is cancelled and the server saves
  // the lines it has (scan-ID-partial.pcd) before serve ends; it used to end with them.
  bool stopping = false;
  QTimer stop_poll;
  QObject::connect(&stop_poll, &QTimer::timeout, &app, [&] {
    if (!stop_requested || stopping) return;
    stopping = true;
    if (device->state() != hardware::ScannerDevice::State::kScanning) {
      app.quit();
      return;
    }
    log("stopping: the scan under way is cancelled and its lines saved first");
    // After the server's own slot (connected first), which saves the scan.
    QObject::connect(device.get(), &hardware::ScannerDevice::scanFinished, &app,
                     [&] { QTimer::singleShot(0, &app, &QCoreApplication::quit); });
    device->cancelScan();
    QTimer::singleShot(kStopScanMs, &app, &QCoreApplication::quit);
  });
  stop_poll.start(kStopPollMs);
  if (seconds > 0) QTimer::singleShot(int(seconds * 1000), &app, [] { stop_requested = true; });
  app.exec();
  const ServerStatistics stats = server.statistics();
  log(QString("stopped: %1 connections accepted, %2 refused, %3 scans")
          .arg(stats.connections_accepted)
          .arg(stats.connections_refused)
          .arg(stats.scans_finished));
  return 0;
}

}  // namespace clearway::cli
