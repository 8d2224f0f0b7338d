// clearway: the operator console.
// clearway [SCAN] [--load SCAN] [--robot-width W] [--robot-length L] [--robot-height H]
//          [--screenshot PNG [--size WxH] [--view operator|top|front|side]]
//          [--measure X1,Y1,X2,Y2] [--goal X,Y] [--deuteranopia] [--threads N]
// With --screenshot it loads and segments the scan, renders, saves a picture of the window and
// exits: 0 when all went well, 1 with a message otherwise. --size sets the window's size, --view
// the 3D camera, --measure draws a measured distance on the map, --goal asks "Can it get there?"
// for a map position (the path or the reason is shown), --deuteranopia saves the picture
// as a person with deuteranopia would see it (Machado 2009), so screenshots are reproducible.
// --threads sets the engine's threads (default kDefaultThreads, as clearway-cli's).

#include <QApplication>
#include <QCommandLineParser>
#include <QCoreApplication>
#include <QSettings>
#include <QTemporaryDir>
#include <QTimer>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string_view>

#include "clearway/memory_tuning.h"
#include "clearway/ui/main_window.h"
#include "clearway/ui/map_view.h"
#include "clearway/ui/palette.h"
#include "clearway/ui/robot_panel.h"
#include "clearway/ui/scene_view.h"
#include "clearway/ui/segmentation_session.h"

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

bool readThreads(const QCommandLineParser& parser, int& threads) {
  if (!parser.isSet("threads")) return true;
  bool ok = false;
  threads = parser.value("threads").toInt(&ok);
  if (!ok || threads < 1 || threads > clearway::kMaxThreads) {
    std::fprintf(stderr, "clearway: --threads needs a whole number from 1 to %d\n",
                 clearway::kMaxThreads);
    return false;
  }
  return true;
}

bool readSize(const QCommandLineParser& parser, QSize& size) {
  if (!parser.isSet("size")) return true;
  const QStringList parts = parser.value("size").split('x');
  bool ok_w = false, ok_h = false;
  if (parts.size() == 2) size = QSize(parts[0].toInt(&ok_w), parts[1].toInt(&ok_h));
  if (!ok_w || !ok_h || size.width() < 320 || size.height() < 240) {
    std::fprintf(stderr, "clearway: --size needs WIDTHxHEIGHT in pixels, at least 320x240\n");
    return false;
  }
  return true;
}

bool readView(const QCommandLineParser& parser, clearway::ui::SceneView::CameraView& view) {
  using View = clearway::ui::SceneView::CameraView;
  const QString name = parser.value("view");
  if (name.isEmpty() || name == "operator") {
    view = View::kBehind;
  } else if (name == "top") {
    view = View::kTop;
  } else if (name == "front") {
    view = View::kFront;
  } else if (name == "side") {
    view = View::kSide;
  } else {
    std::fprintf(stderr, "clearway: --view must be operator, top, front or side, not '%s'\n",
                 qPrintable(name));
    return false;
  }
  return true;
}

bool readMeasure(const QCommandLineParser& parser, std::vector<double>& points) {
  if (!parser.isSet("measure")) return true;
  for (const QString& part : parser.value("measure").split(',')) {
    bool ok = false;
    points.push_back(part.toDouble(&ok));
    if (!ok) points.clear();
  }
  if (points.size() != 4) {
    std::fprintf(stderr, "clearway: --measure needs X1,Y1,X2,Y2 in map metres\n");
    return false;
  }
  return true;
}

bool readGoal(const QCommandLineParser& parser, std::optional<QPointF>& goal) {
  if (!parser.isSet("goal")) return true;
  const QStringList parts = parser.value("goal").split(',');
  bool ok_x = false, ok_y = false;
  if (parts.size() == 2) goal = QPointF(parts[0].toDouble(&ok_x), parts[1].toDouble(&ok_y));
  if (!ok_x || !ok_y) {
    std::fprintf(stderr, "clearway: --goal needs X,Y in map metres\n");
    return false;
  }
  return true;
}

// Measures between two map positions, exactly: clicks at them would be placed to a pixel.
void measureOnMap(clearway::ui::MapView& map, const std::vector<double>& points) {
  map.setMeasuring(true);
  map.measureBetween(QPointF(points[0], points[1]), QPointF(points[2], points[3]));
}

// The console's command line, for the parser of whichever application runs.
void describeOptions(QCommandLineParser& parser) {
  parser.setApplicationDescription("Clearway operator console");
  parser.addHelpOption();
  parser.addPositionalArgument("scan", "Scan file to open");
  parser.addOption({"load", "Scan file to open.", "scan"});
  parser.addOption({"robot-width", "Robot width [m].", "metres"});
  parser.addOption({"robot-length", "Robot length [m].", "metres"});
  parser.addOption({"robot-height", "Robot height [m].", "metres"});
  parser.addOption(
      {"screenshot", "Save a picture of the window once the scan is shown, then exit.", "png"});
  parser.addOption({"size", "Window size for --screenshot, e.g. 1366x768.", "WxH"});
  parser.addOption({"view", "3D camera: operator (default), top, front or side.", "view"});
  parser.addOption({"measure", "Measure on the map between two points [m].", "x1,y1,x2,y2"});
  parser.addOption({"deuteranopia", "Save the screenshot as seen with deuteranopia."});
  parser.addOption({"threads",
                    QString("Threads the engine uses (default %1).").arg(clearway::kDefaultThreads),
                    "n"});
  parser.addOption(
      {"goal", "With --screenshot: ask \"Can it get there?\" for a map position [m].", "x,y"});
}

bool asksForHelp(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view argument = argv[i];
    if (argument == "-h" || argument == "--help" || argument == "-?" || argument == "--help-all")
      return true;
  }
  return false;
}

// Where Qt would find no display to open it aborts with its own words; say ours instead.
bool hasADisplay() {
  const auto set = [](const char* name) {
    const char* value = std::getenv(name);
    return value && *value;
  };
  return set("DISPLAY") || set("WAYLAND_DISPLAY") || set("QT_QPA_PLATFORM");
}

}  // namespace

int main(int argc, char** argv) {
  if (asksForHelp(argc, argv)) {
    // Help needs no window, and so no display: a headless machine asking for it got an abort.
    QCoreApplication application(argc, argv);
    QCoreApplication::setApplicationName("Clearway");
    QCommandLineParser parser;
    describeOptions(parser);
    parser.process(application);  // prints the help and exits
    return 0;
  }
  if (!hasADisplay()) {
    std::fprintf(stderr,
                 "clearway: no display to open the console on (DISPLAY and WAYLAND_DISPLAY are "
                 "unset). Run it under xvfb-run for screenshots, or use clearway-cli segment SCAN "
                 "-o DIR for the pipeline without a window (scripts/run does so by itself).\n");
    return 2;
  }
  clearway::keepFreedMemoryForReuse();
  clearway::ui::SceneView::prepareApplication();
  QApplication application(argc, argv);
  QApplication::setApplicationName("Clearway");
  QApplication::setOrganizationName("Clearway");

  QCommandLineParser parser;
  describeOptions(parser);
  parser.process(application);

  // A screenshot shows the console as at its first start: settings of its own, not the user's
  // recent scans, layout or parameters.
  QTemporaryDir screenshot_settings;
  if (parser.isSet("screenshot")) {
    QSettings::setDefaultFormat(QSettings::IniFormat);
    QSettings::setPath(QSettings::IniFormat, QSettings::UserScope, screenshot_settings.path());
  }
  clearway::ui::MainWindow window;
  clearway::RobotParams robot = clearway::robotPresets().front();
  if (!readLength(parser, "robot-width", robot.width) ||
      !readLength(parser, "robot-length", robot.length) ||
      !readLength(parser, "robot-height", robot.height))
    return 2;
  QSize size;
  clearway::ui::SceneView::CameraView view = clearway::ui::SceneView::CameraView::kBehind;
  std::vector<double> measure;
  std::optional<QPointF> goal;
  int threads = clearway::kDefaultThreads;
  if (!readSize(parser, size) || !readView(parser, view) || !readMeasure(parser, measure) ||
      !readGoal(parser, goal) || !readThreads(parser, threads))
    return 2;
  window.session()->setThreads(threads);
  if (const std::string refused = window.robotPanel()->takeRobot(robot); !refused.empty()) {
    std::fprintf(stderr, "clearway: %s\n", refused.c_str());
    return 2;
  }
  if (size.isValid()) window.resize(size);
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
    const bool deuteranopia = parser.isSet("deuteranopia");
    QObject::connect(&window, &clearway::ui::MainWindow::resultShown, &application, [&] {
      // The robot given on the command line may still be re-running: wait for the last result.
      if (window.session()->busy()) return;
      window.sceneView()->setCameraView(view);
      if (!measure.empty()) measureOnMap(*window.mapView(), measure);
      if (goal) window.canItGetThere(goal->x(), goal->y());
      // Let the window paint the new result before taking the picture.
      QTimer::singleShot(300, &application, [&] {
        if (!deuteranopia) {
          QApplication::exit(window.saveScreenshot(screenshot) ? 0 : 1);
          return;
        }
        const QImage seen = clearway::ui::simulateDeuteranopia(window.grab().toImage());
        if (!seen.save(screenshot)) {
          std::fprintf(stderr, "clearway: cannot save the screenshot to %s\n",
                       qPrintable(screenshot));
          QApplication::exit(1);
          return;
        }
        QApplication::exit(0);
      });
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
