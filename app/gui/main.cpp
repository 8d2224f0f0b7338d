// clearway: the operator console.
// clearway [SCAN] [--load SCAN] [--robot-width W] [--robot-length L] [--robot-height H]
//          [--screenshot PNG]
// With --screenshot it loads and segments the scan, renders, saves a picture of the window and
// exits: 0 when all went well, 1 with a message otherwise.

#include <QApplication>
#include <QCommandLineParser>
#include <QTimer>
#include <cstdio>

#include "clearway/memory_tuning.h"
#include "clearway/ui/main_window.h"
#include "clearway/ui/robot_panel.h"
#include "clearway/ui/scene_view.h"

namespace {

bool readLength(const QCommandLineParser& parser, const QString& name, double& value) {
  if (!parser.isSet(name)) return true;
  bool ok = false;
  const double parsed = parser.value(name).toDouble(&ok);
  if (!ok || parsed <= 0.0) {
    std::fprintf(stderr, "clearway: --%s needs a positive length in metres\n", qPrintable(name));
    return false;
  }
  value = parsed;
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  clearway::keepFreedMemoryForReuse();
  clearway::ui::SceneView::prepareApplication();
  QApplication application(argc, argv);
  QApplication::setApplicationName("Clearway");
  QApplication::setOrganizationName("Clearway");

  QCommandLineParser parser;
  parser.setApplicationDescription("Clearway operator console");
  parser.addHelpOption();
  parser.addPositionalArgument("scan", "Scan file to open");
  parser.addOption({"load", "Scan file to open.", "scan"});
  parser.addOption({"robot-width", "Robot width [m].", "metres"});
  parser.addOption({"robot-length", "Robot length [m].", "metres"});
  parser.addOption({"robot-height", "Robot height [m].", "metres"});
  parser.addOption(
      {"screenshot", "Save a picture of the window once the scan is shown, then exit.", "png"});
  parser.process(application);

  clearway::ui::MainWindow window;
  clearway::RobotParams robot = clearway::robotPresets().front();
  if (!readLength(parser, "robot-width", robot.width) ||
      !readLength(parser, "robot-length", robot.length) ||
      !readLength(parser, "robot-height", robot.height))
    return 2;
  window.setRobot(robot);
  window.show();

  QString scan = parser.value("load");
  if (scan.isEmpty() && !parser.positionalArguments().isEmpty())
    scan = parser.positionalArguments().first();
  const QString screenshot = parser.value("screenshot");
  if (!screenshot.isEmpty()) {
    if (scan.isEmpty()) {
      std::fprintf(stderr, "clearway: --screenshot needs a scan to show\n");
      return 2;
    }
    QObject::connect(&window, &clearway::ui::MainWindow::resultShown, &application, [&] {
      // Let the window paint the new result before taking the picture.
      QTimer::singleShot(100, &application,
                         [&] { QApplication::exit(window.saveScreenshot(screenshot) ? 0 : 1); });
    });
    QObject::connect(&window, &clearway::ui::MainWindow::failureShown, &application,
                     [&](const QString& reason) {
                       std::fprintf(stderr, "clearway: %s\n", qPrintable(reason));
                       QApplication::exit(1);
                     });
  }
  if (!scan.isEmpty()) window.openScan(scan);
  return QApplication::exec();
}
