// clearway-cli acquire --remote HOST:PORT --credentials DIR: one scan from `clearway-cli serve` on
// the robot, through the same RemoteRosi the console uses (reconnects and resumes by itself).

#include <unistd.h>

#include <QCoreApplication>
#include <QElapsedTimer>
#include <QSocketNotifier>
#include <QTimer>
#include <iostream>

#include "arguments.h"
#include "clearway/hardware/acquisition_files.h"
#include "clearway/hardware/remote_rosi.h"
#include "clearway/io/scan_io.h"
#include "commands.h"
#include "host_port.h"
#include "stop_signals.h"

namespace clearway::cli {

using namespace hardware::remote;

int runRemoteAcquire(const std::vector<std::string>& words) {
  const Arguments arguments(words, {"watch"},
                            {"remote", "credentials", "lines", "speed", "o", "output", "give-up"});
  arguments.expectPositional(0,
                             "clearway-cli acquire --remote HOST:PORT --credentials DIR [--lines "
                             "N] -o SCAN.pcd");
  const auto output = arguments.option("o") ? arguments.option("o") : arguments.option("output");
  const auto credentials_dir = arguments.option("credentials");
  if (!output || !credentials_dir)
    throw UsageError("--credentials DIR and -o SCAN.pcd are required with --remote");
  // Checked before anything starts, as for a serial acquisition: a typo never costs a scan.
  if (const std::string problem = hardware::checkOutputPath(*output); !problem.empty())
    throw UsageError(problem);
  const auto [host, port] = parseHostPort(*arguments.option("remote"), false);

  RemoteOptions options;
  options.host = host;
  options.port = port;
  options.client_name = "clearway-cli acquire";
  options.role = arguments.flag("watch") ? Role::kWatch : Role::kControl;
  options.give_up_after_ms = int(arguments.number("give-up", 120.0, 1.0, 86400.0) * 1000);
  try {
    options.credentials = loadConsoleCredentials(QString::fromStdString(*credentials_dir));
  } catch (const CredentialsError& error) {
    std::cerr << "clearway-cli acquire: " << error.what() << "\n";
    return 1;
  }
  hardware::ScanRequest request;
  request.lines = int(arguments.integer("lines", 0, 0, kMaxLinesPerScan));
  request.turntable_speed_deg_s = arguments.number("speed", 0.0, 0.0, 360.0);

  int argc = 1;
  char name[] = "clearway-cli";
  char* argv[] = {name, nullptr};
  QCoreApplication app(argc, argv);
  RemoteRosi rosi(options);
  int exit_code = 1;
  QString last_failure;
  QElapsedTimer clock;
  clock.start();
  QObject::connect(&rosi, &RemoteRosi::linkStatusChanged, [](const QString& link) {
    std::cerr << "link: " << link.toStdString() << std::endl;
  });
  QObject::connect(&rosi, &RemoteRosi::notice, [](const QString& text) {
    std::cerr << "robot: " << text.toStdString() << std::endl;
  });
  // Once interrupted, that is the reason (the robot's "cancelled" follows from it).
  bool interrupted = false;
  QObject::connect(&rosi, &RemoteRosi::failed, [&](const QString& reason) {
    if (!interrupted) last_failure = reason;
    if (rosi.state() != hardware::ScannerDevice::State::kScanning) app.exit();
  });
  QObject::connect(&rosi, &RemoteRosi::stateChanged, [&](hardware::ScannerDevice::State state) {
    // A watcher waits for the controlling console's scan; a controller starts one. Asked for
    // control and given watching (another console has it), nothing would ever start: say so.
    if (state != hardware::ScannerDevice::State::kIdle || !clock.isValid()) return;
    clock.invalidate();
    if (rosi.role() == Role::kControl) {
      rosi.startScan(request);
    } else if (options.role == Role::kControl) {
      last_failure =
          "another console controls the scanner: no scan started (with --watch, its "
          "scan is received instead)";
      app.exit();
    }
  });
  // The lines so far: what is kept if the robot cannot answer a stop.
  std::shared_ptr<const Scan> so_far;
  QObject::connect(&rosi, &RemoteRosi::linesArrived,
                   [&](std::shared_ptr<const Scan> lines) { so_far = std::move(lines); });
  auto keepPartial = [&](const Scan& scan) {
    if (scan.empty()) return;
    const std::filesystem::path partial = hardware::partialPathFor(*output);
    saveRosiPcd(scan, partial);
    std::cerr << "clearway-cli acquire: the " << scan.lines.size() << " lines that arrived are in "
              << partial.string() << "\n";
  };
  // Ctrl-C or SIGTERM: the robot is told to stop and answers with the lines it has, which are
  // kept; without an answer in kStopAnswerMs (the link is down), the lines received so far are.
  constexpr int kStopAnswerMs = 10'000;
  const StopSignals stop_signals;
  QSocketNotifier stop_notifier(stop_signals.descriptor(), QSocketNotifier::Read);
  QObject::connect(&stop_notifier, &QSocketNotifier::activated, [&] {
    char byte = 0;
    while (::read(stop_signals.descriptor(), &byte, 1) == 1) {
    }
    interrupted = true;
    last_failure = QString("interrupted by %1").arg(stop_signals.lastSignalName());
    if (rosi.state() != hardware::ScannerDevice::State::kScanning) {
      app.exit();
      return;
    }
    std::cerr << "clearway-cli acquire: " << stop_signals.lastSignalName()
              << ": asking the robot to stop the scan" << std::endl;
    rosi.cancelScan();
    QTimer::singleShot(kStopAnswerMs, &app, [&] {
      try {
        if (so_far) keepPartial(*so_far);
      } catch (const std::exception& error) {
        std::cerr << "clearway-cli acquire: " << error.what() << "\n";
      }
      app.exit();
    });
  });
  QObject::connect(
      &rosi, &RemoteRosi::scanFinished, [&](std::shared_ptr<const Scan> scan, bool complete) {
        const LinkStatistics stats = rosi.linkStatistics();
        try {
          if (complete) {
            saveRosiPcd(*scan, *output);
            std::cout << "acquired " << scan->lines.size() << " lines, " << scan->size()
                      << " points: " << *output << " (" << stats.bytes_received
                      << " bytes received, " << stats.reconnections << " reconnections, "
                      << stats.duplicate_lines_dropped << " repeated lines dropped)" << std::endl;
            exit_code = 0;
          } else {
            keepPartial(*scan);
          }
        } catch (const std::exception& error) {
          std::cerr << "clearway-cli acquire: " << error.what() << "\n";
        }
        app.exit();
      });
  rosi.connectDevice();
  app.exec();
  if (exit_code != 0 && !last_failure.isEmpty())
    std::cerr << "clearway-cli acquire: " << last_failure.toStdString() << "\n";
  return exit_code;
}

}  // namespace clearway::cli
