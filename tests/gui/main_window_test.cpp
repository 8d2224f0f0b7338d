// The operator console under QT_QPA_PLATFORM=offscreen: open, segment, change the robot, bad files,
// cancel, close while working. Settings and paths are isolated (QStandardPaths test mode).

#include <Eigen/Geometry>
#include <QDoubleSpinBox>
#include <QFile>
#include <QLabel>
#include <QMessageBox>
#include <QSettings>
#include <QSignalSpy>
#include <QSlider>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QTextStream>
#include <QtTest>
#include <cmath>
#include <numbers>
#include <random>

#include "clearway/io/scan_io.h"
#include "clearway/sim/builtin_scenes.h"
#include "clearway/sim/rosi_simulator.h"
#include "clearway/ui/main_window.h"
#include "clearway/ui/map_view.h"
#include "clearway/ui/palette.h"
#include "clearway/ui/robot_panel.h"
#include "clearway/ui/scene_view.h"
#include "clearway/ui/segmentation_session.h"

using clearway::ui::MainWindow;

namespace {

constexpr int kTimeoutMs = 30000;

// Traversable pixels in the map pane's image: how much the map shows as traversable.
const QRgb kTraversable = clearway::ui::cellColour(clearway::CellLabel::kTraversable,
                                                   clearway::ui::PaletteKind::kColourBlindSafe)
                              .rgb();
int greenPixels(const QImage& image) {
  int count = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      count += image.pixel(x, y) == kTraversable;
  return count;
}

// The scene scanned with `lines` lines, the turntable's axis tilted by `tilt_deg` about x (as
// `clearway-cli simulate --tilt` does).
QString simulate(const QTemporaryDir& directory, const std::string& scene_name, int lines,
                 double tilt_deg = 0.0) {
  const clearway::sim::Scene scene = *clearway::sim::builtinScene(scene_name);
  clearway::sim::SensorModel sensor;
  sensor.lines = lines;
  clearway::sim::ScannerPlacement placement = clearway::sim::defaultPlacement(scene);
  placement.axis =
      Eigen::AngleAxisd(tilt_deg * M_PI / 180.0, Eigen::Vector3d::UnitX()) * placement.axis;
  const auto simulated = clearway::sim::simulateRosi(scene, sensor, placement);
  const QString path = directory.filePath(QString::fromStdString(scene_name) + ".pcd");
  clearway::saveRosiPcd(simulated.scan, path.toStdString());
  return path;
}

// The garage as an acquisition that ended early leaves it: the first `kept` of 200 lines.
QString partialGarage(const QTemporaryDir& directory, const QString& name, std::size_t kept) {
  const clearway::sim::Scene scene = *clearway::sim::builtinScene("garage");
  auto simulated = clearway::sim::simulateRosi(scene, clearway::sim::SensorModel{},
                                               clearway::sim::defaultPlacement(scene));
  clearway::Scan& scan = simulated.scan;
  scan.lines.resize(std::min(kept, scan.lines.size()));
  const std::size_t points = scan.lines.back().first + scan.lines.back().count;
  scan.points.resize(points);
  scan.status.resize(points);
  if (!scan.intensity.empty()) scan.intensity.resize(points);
  if (!scan.alpha.empty()) scan.alpha.resize(points);
  const QString path = directory.filePath(name);
  clearway::saveRosiPcd(scan, path.toStdString());
  return path;
}

}  // namespace

class MainWindowTest : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase() {
    // Settings of their own, empty: nothing from other tests or earlier runs.
    QStandardPaths::setTestModeEnabled(true);
    QCoreApplication::setApplicationName("clearway-window-test");
    QSettings().clear();
    QVERIFY(directory_.isValid());
  }

  void opensAndSegmentsTheBundledScan() {
    MainWindow window;
    window.show();
    QSignalSpy shown(&window, &MainWindow::resultShown);
    window.openScan(CLEARWAY_SAMPLES_DIR "/garage.pcd");
    QVERIFY(shown.wait(kTimeoutMs));
    QCOMPARE(shown.takeFirst().at(0).toBool(), true);
    QVERIFY(greenPixels(window.mapView()->image()) > 1000);
    QVERIFY(!window.findChild<QLabel*>("trustBanner")->isVisible());
    // No OpenGL offscreen: the 3D view says so and everything else works.
    QVERIFY(!window.sceneView()->hasRenderer());
    QVERIFY(window.findChild<QLabel*>("sceneViewPlaceholder"));
  }

  void wideningTheRobotShrinksTheTraversableArea() {
    MainWindow window;
    window.show();
    QSignalSpy shown(&window, &MainWindow::resultShown);
    window.openScan(CLEARWAY_SAMPLES_DIR "/garage.pcd");
    QVERIFY(shown.wait(kTimeoutMs));
    const int narrow = greenPixels(window.mapView()->image());
    auto* slider = window.findChild<QSlider*>("robot_width_slider");
    QVERIFY(slider);
    slider->setValue(120);  // 1.2 m
    QVERIFY(shown.wait(kTimeoutMs));
    const int wide = greenPixels(window.mapView()->image());
    QVERIFY2(wide < narrow,
             qPrintable(QString("%1 green at 1.2 m vs %2 at 0.85 m").arg(wide).arg(narrow)));
  }

  void aScanWithoutGroundShowsABannerAndNoGreen() {
    MainWindow window;
    window.show();
    QSignalSpy shown(&window, &MainWindow::resultShown);
    window.openScan(simulate(directory_, "no-ground", 100));
    QVERIFY(shown.wait(kTimeoutMs));
    QCOMPARE(shown.takeFirst().at(0).toBool(), false);
    auto* banner = window.findChild<QLabel*>("trustBanner");
    QVERIFY(banner->isVisible());
    QVERIFY(banner->text().contains("no ground"));
    QCOMPARE(greenPixels(window.mapView()->image()), 0);
  }

  // A scan whose acquisition ended early covers part of the turn, and its map showed no more than
  // a complete one's: the banner says it is partial, why it ended, and what that means. Known
  // from the acquisition's record beside the scan (SCAN.acquisition.json), or, without one, from
  // the name Clearway gives a partial scan (the console's rosi-...-partial.pcd).
  void aPartialScanSaysSoInTheBanner() {
    const QString recorded = partialGarage(directory_, "cut.partial.pcd", 90);
    {
      QFile report(directory_.filePath("cut.partial.acquisition.json"));
      QVERIFY(report.open(QIODevice::WriteOnly));
      report.write(R"({"version": 1, "scan": "cut.partial.pcd", "complete": false,
          "reason": "the turntable sent no angle for 1000 ms", "lines": 90, "lines_received": 90,
          "dropped_lines": 0, "untagged_lines": 0, "stopped_by_signal": false,
          "pose_source": null})");
    }
    MainWindow window;
    window.show();
    QSignalSpy shown(&window, &MainWindow::resultShown);
    auto* banner = window.findChild<QLabel*>("trustBanner");
    window.openScan(recorded);
    QVERIFY(shown.wait(kTimeoutMs));
    QVERIFY(banner->isVisible());
    QVERIFY2(banner->text().contains("Partial scan") &&
                 banner->text().contains("the turntable sent no angle for 1000 ms") &&
                 banner->text().contains("not free"),
             qPrintable(banner->text()));
    // No record beside it: the name the console gives a scan it did not finish.
    window.openScan(partialGarage(directory_, "rosi-20240501-101500-000-partial.pcd", 90));
    QVERIFY(shown.wait(kTimeoutMs));
    QVERIFY(banner->isVisible());
    QVERIFY2(banner->text().contains("Partial scan"), qPrintable(banner->text()));
    // A complete scan: no banner.
    window.openScan(CLEARWAY_SAMPLES_DIR "/garage.pcd");
    QVERIFY(shown.wait(kTimeoutMs));
    QVERIFY2(!banner->isVisible(), qPrintable(banner->text()));
  }

  // Ground found, but nothing green: the banner says why (amber, not the untrusted red).
  void aScanTooSparseForGreenSaysSoInTheBanner() {
    MainWindow window;
    window.show();
    QSignalSpy shown(&window, &MainWindow::resultShown);
    window.openScan(simulate(directory_, "garage", 20, 25.0));
    QVERIFY(shown.wait(kTimeoutMs));
    QCOMPARE(shown.takeFirst().at(0).toBool(), true);
    auto* banner = window.findChild<QLabel*>("trustBanner");
    QVERIFY(banner->isVisible());
    QVERIFY2(banner->text().contains("too sparse"), qPrintable(banner->text()));
    // Said once: the reason names what is not shown itself, with no prefix repeating it.
    QVERIFY2(banner->text().count("traversable") == 1, qPrintable(banner->text()));
    QCOMPARE(greenPixels(window.mapView()->image()), 0);
  }

  // A frame kept firing after firing whose lasers overlap in elevation (eight lasers 1 deg apart,
  // each spread 1.5 deg either way): the loader cannot find its rings, and the console says so in
  // the scan panel and leads the banner's reason with it.
  void aFrameWhoseRingsCannotBeFoundSaysSo() {
    const QString file = directory_.filePath("overlapping_firings.pcd");
    {
      QFile pcd(file);
      QVERIFY(pcd.open(QIODevice::WriteOnly | QIODevice::Text));
      QTextStream out(&pcd);
      constexpr int kColumns = 360, kLasers = 8;
      out << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH "
          << kColumns * kLasers << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS "
          << kColumns * kLasers << "\nDATA ascii\n";
      std::mt19937 random(5);
      std::uniform_real_distribution<double> spread(-1.5, 1.5);
      constexpr double kDeg = std::numbers::pi / 180.0;
      for (int k = 0; k < kColumns; ++k)
        for (const int laser : {5, 1, 6, 2, 7, 3, 4, 0}) {
          const double elevation = (-10.0 + laser + spread(random)) * kDeg;
          const double azimuth = (k + 0.5) * kDeg;
          out << 10.0 * std::cos(elevation) * std::cos(azimuth) << ' '
              << 10.0 * std::cos(elevation) * std::sin(azimuth) << ' ' << 10.0 * std::sin(elevation)
              << '\n';
        }
    }
    MainWindow window;
    window.show();
    QSignalSpy shown(&window, &MainWindow::resultShown);
    window.openScan(file);
    QVERIFY(shown.wait(kTimeoutMs));
    const QString info = window.findChild<QLabel*>("scanInfo")->text();
    QVERIFY2(info.contains("Caution") && info.contains("firing after firing"), qPrintable(info));
    auto* banner = window.findChild<QLabel*>("trustBanner");
    QVERIFY(banner->isVisible());
    QVERIFY2(banner->text().contains("firing after firing"), qPrintable(banner->text()));
    QCOMPARE(greenPixels(window.mapView()->image()), 0);
  }

  void aLowerMaxSlopeDropsTheRampFromTheGround() {
    MainWindow window;
    window.show();
    QSignalSpy shown(&window, &MainWindow::resultShown);
    window.openScan(CLEARWAY_SAMPLES_DIR "/hallway.pcd");
    QVERIFY(shown.wait(kTimeoutMs));
    const int with_ramp = greenPixels(window.mapView()->image());
    auto* slope = window.findChild<QDoubleSpinBox*>("ground_max_slope_deg_spin");
    QVERIFY(slope);
    slope->setValue(5);  // the ramp climbs 12 degrees
    QVERIFY(shown.wait(kTimeoutMs));
    const int without_ramp = greenPixels(window.mapView()->image());
    QVERIFY2(without_ramp < with_ramp,
             qPrintable(QString("%1 vs %2").arg(without_ramp).arg(with_ramp)));
  }

  void aCorruptFileGivesAnErrorDialogNotACrash() {
    MainWindow window;
    window.show();
    const QString path = directory_.filePath("corrupt.pcd");
    QFile file(path);
    QVERIFY(file.open(QIODevice::WriteOnly));
    file.write(
        "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1000000\nHEIGHT 1\nDATA "
        "binary\nxx");
    file.close();
    QSignalSpy failed(&window, &MainWindow::failureShown);
    window.openScan(path);
    QVERIFY(failed.wait(kTimeoutMs));
    QVERIFY(failed.takeFirst().at(0).toString().contains("corrupt.pcd"));
    auto* dialog = window.findChild<QMessageBox*>("errorDialog");
    QVERIFY(dialog);
    QVERIFY(dialog->isVisible());
    dialog->close();
  }

  void aRobotChangeSharesTheAnalysisAndUsesTheSessionsThreads() {
    MainWindow window;
    window.show();
    QSignalSpy shown(&window, &MainWindow::resultShown);
    window.openScan(CLEARWAY_SAMPLES_DIR "/garage.pcd");
    QVERIFY(shown.wait(kTimeoutMs));
    QTRY_VERIFY_WITH_TIMEOUT(!window.session()->busy(), kTimeoutMs);
    const auto first = window.shownResult().result;
    QVERIFY(first && first->analysis);
    clearway::ui::SegmentationSession& session = *window.session();
    QCOMPARE(session.threads(), clearway::kDefaultThreads);
    session.setThreads(0);
    QCOMPARE(session.threads(), 1);  // at least one
    session.setThreads(1000);
    QCOMPARE(session.threads(), clearway::kMaxThreads);
    session.setThreads(1);
    clearway::RobotParams robot = session.params().robot;
    robot.width += 0.1;
    session.setRobot(robot);
    QTRY_VERIFY_WITH_TIMEOUT(window.shownResult().result->robot.width == robot.width, kTimeoutMs);
    // The re-run for the new robot holds the very analysis of the first run, not a copy.
    QCOMPARE(window.shownResult().result->analysis.get(), first->analysis.get());
  }

  void cancelStopsALongJob() {
    MainWindow window;
    window.show();
    const QString big = simulate(directory_, "garage", 6000);  // ~1.1 M points
    QSignalSpy failed(&window, &MainWindow::failureShown);
    QSignalSpy cancelled(&window, &MainWindow::cancelShown);
    QSignalSpy shown(&window, &MainWindow::resultShown);
    window.openScan(big);
    window.session()->cancel();
    QTRY_VERIFY_WITH_TIMEOUT(cancelled.count() + shown.count() > 0, kTimeoutMs);
    QCOMPARE(failed.count(), 0);  // a cancel is no failure
  }

  // A robot's re-run of a 1.1M-point scan showed "Done 100 %" beside a Cancel that did nothing.
  // It names itself and stops when cancelled, leaving the previous robot's map as its title says.
  void aRobotRerunReportsProgressAndCanBeCancelled() {
    MainWindow window;
    window.show();
    const QString big = directory_.filePath("garage.pcd");
    if (!QFile::exists(big)) simulate(directory_, "garage", 6000);
    QSignalSpy shown(&window, &MainWindow::resultShown);
    QSignalSpy cancelled(&window, &MainWindow::cancelShown);
    QSignalSpy failed(&window, &MainWindow::failureShown);
    window.openScan(big);
    QVERIFY(shown.wait(kTimeoutMs));
    const double old_width = window.shownResult().result->robot.width;
    QSignalSpy progress(window.session(), &clearway::ui::SegmentationSession::progress);
    clearway::RobotParams robot = window.session()->params().robot;
    robot.width += 0.1;
    window.session()->setRobot(robot);
    QTRY_VERIFY_WITH_TIMEOUT(window.session()->busy(), kTimeoutMs);  // past the debounce
    window.session()->cancel();
    QTRY_VERIFY_WITH_TIMEOUT(cancelled.count() + shown.count() > 1, kTimeoutMs);
    QCOMPARE(failed.count(), 0);
    bool named = false;
    for (const QList<QVariant>& signal : progress)
      named = named || signal.at(1).toString() == "New robot";
    QVERIFY(named);
    if (cancelled.count() > 0) {
      QCOMPARE(window.shownResult().result->robot.width, old_width);
      QVERIFY(window.windowTitle().contains(QString::number(old_width, 'f', 2)));
    }
  }

  void closingTheWindowWhileAJobRunsIsSafe() {
    const QString big = directory_.filePath("garage.pcd");
    if (!QFile::exists(big)) simulate(directory_, "garage", 6000);
    auto* window = new MainWindow;
    window->show();
    window->openScan(big);
    QTest::qWait(20);
    delete window;  // must cancel and wait, not crash
    QVERIFY(true);
  }

 private:
  QTemporaryDir directory_;
};

QTEST_MAIN(MainWindowTest)
#include "main_window_test.moc"
