// Issue #13 under QT_QPA_PLATFORM=offscreen: what the console shows is the truth (defects 1-3), the
// window fits, remembers and has a View menu and shortcuts (7), and it speaks to operators (8).
// Settings are isolated (QStandardPaths test mode).

#include <QAbstractItemView>
#include <QAction>
#include <QComboBox>
#include <QDialogButtonBox>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QFile>
#include <QGroupBox>
#include <QJsonDocument>
#include <QJsonObject>
#include <QLabel>
#include <QLineEdit>
#include <QMenu>
#include <QMenuBar>
#include <QMessageBox>
#include <QProgressBar>
#include <QPushButton>
#include <QScreen>
#include <QScrollArea>
#include <QScrollBar>
#include <QSettings>
#include <QSignalSpy>
#include <QSlider>
#include <QSpinBox>
#include <QStandardPaths>
#include <QStatusBar>
#include <QTemporaryDir>
#include <QToolButton>
#include <QtTest>

#include "clearway/io/scan_io.h"
#include "clearway/pose.h"
#include "clearway/ui/hardware_panel.h"
#include "clearway/ui/main_window.h"
#include "clearway/ui/map_view.h"
#include "clearway/ui/parameters_dialog.h"
#include "clearway/ui/robot_panel.h"
#include "clearway/ui/scene_view.h"
#include "clearway/ui/segmentation_session.h"

using namespace clearway::ui;

Q_DECLARE_METATYPE(std::shared_ptr<const clearway::Scan>)

namespace {

constexpr int kTimeoutMs = 30000;
// Longer than the robot debounce and a re-run of the garage: a result would have come by then.
constexpr int kSettleMs = 3500;

QString writeCorruptScan(const QTemporaryDir& directory) {
  const QString path = directory.filePath("corrupt.pcd");
  QFile file(path);
  file.open(QIODevice::WriteOnly);
  file.write(
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1000000\nHEIGHT 1\nDATA "
      "binary\nxx");
  return path;
}

// The part of `widget` on screen: inside every parent up to `window`, and the window.
QSize shownSize(const QWidget* widget, const QWidget* window) {
  QRect shown = widget->rect();
  for (const QWidget* child = widget; child != window; child = child->parentWidget())
    shown = shown.translated(child->pos()).intersected(child->parentWidget()->rect());
  return shown.size();
}

bool fullyShown(const QWidget* widget, const QWidget* window) {
  return shownSize(widget, window) == widget->size();
}

// All of a control on screen; of a list, which scrolls its own items, its full width and at least
// the height it needs to be used.
bool usable(const QWidget* control, const QWidget* window) {
  if (!qobject_cast<const QAbstractItemView*>(control)) return fullyShown(control, window);
  const QSize shown = shownSize(control, window);
  return shown.width() == control->width() &&
         shown.height() >= std::min(control->height(), control->minimumSizeHint().height());
}

// What the operator clicks, types into or drags in a panel.
bool isControl(const QWidget* widget) {
  return qobject_cast<const QAbstractButton*>(widget) || qobject_cast<const QLineEdit*>(widget) ||
         qobject_cast<const QAbstractSpinBox*>(widget) || qobject_cast<const QComboBox*>(widget) ||
         qobject_cast<const QAbstractSlider*>(widget) ||
         qobject_cast<const QAbstractItemView*>(widget);
}

// The visible controls of `panel` that cannot be brought on screen (usable), scrolling the panel's
// scroll area to each as the operator would.
QStringList unreachableControls(QWidget* panel, const QWidget* window) {
  QStringList unreachable;
  for (QWidget* control : panel->findChildren<QWidget*>()) {
    if (!isControl(control) || !control->isVisibleTo(window)) continue;
    // A spin box's line edit, a combo box's view: parts of a control already counted; a scroll
    // bar is how the rest is reached.
    if (qobject_cast<QAbstractSpinBox*>(control->parentWidget()) ||
        qobject_cast<QComboBox*>(control->parentWidget()) || qobject_cast<QScrollBar*>(control))
      continue;
    for (QWidget* ancestor = control->parentWidget(); ancestor; ancestor = ancestor->parentWidget())
      if (auto* scroll = qobject_cast<QScrollArea*>(ancestor);
          scroll && scroll->widget() && scroll->widget()->isAncestorOf(control)) {
        // ensureWidgetVisible brings only a spin box's or line edit's cursor into view.
        const QPoint centre = control->mapTo(scroll->widget(), control->rect().center());
        scroll->ensureVisible(centre.x(), centre.y(), control->width() / 2 + 1,
                              control->height() / 2 + 1);
        break;
      }
    if (!usable(control, window))
      unreachable << QString("%1 (%2) at %3,%4 %5x%6")
                         .arg(control->objectName(), control->metaObject()->className())
                         .arg(control->mapTo(window, QPoint()).x())
                         .arg(control->mapTo(window, QPoint()).y())
                         .arg(control->width())
                         .arg(control->height());
  }
  return unreachable;
}

void closeErrorDialogs(QWidget& window) {
  for (auto* dialog : window.findChildren<QMessageBox*>("errorDialog"))
    dialog->close();
}

}  // namespace

class ConsoleTruthTest : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase() {
    QStandardPaths::setTestModeEnabled(true);
    QCoreApplication::setApplicationName("clearway-truth-test");
    QSettings().clear();
    qRegisterMetaType<std::shared_ptr<const clearway::Scan>>();
    QVERIFY(directory_.isValid());
  }

  void init() { QSettings().clear(); }

  // Defect 1: a failed open used to leave the previous map on screen, green through the door.
  void aFailedOpenClearsTheViewsAndTheyStayClear() {
    MainWindow window;
    window.show();
    QSignalSpy shown(&window, &MainWindow::resultShown);
    QSignalSpy failed(&window, &MainWindow::failureShown);
    window.openScan(CLEARWAY_SAMPLES_DIR "/garage.pcd");
    QVERIFY(shown.wait(kTimeoutMs));
    QVERIFY(window.mapView()->hasResult());
    QVERIFY(window.windowTitle().contains("garage.pcd"));
    window.openScan(writeCorruptScan(directory_));
    QVERIFY(failed.wait(kTimeoutMs));
    closeErrorDialogs(window);
    QVERIFY(!window.mapView()->hasResult());
    QVERIFY(window.mapView()->image().isNull());
    QVERIFY(!window.sceneView()->shownScan());
    QVERIFY(!window.windowTitle().contains("garage.pcd"));
    // A new robot cannot bring the old scan's map back.
    window.findChild<QDoubleSpinBox*>("robot_width_spin")->setValue(1.5);
    QTest::qWait(kSettleMs);
    QCOMPARE(shown.count(), 1);
    QVERIFY(!window.mapView()->hasResult());
  }

  void aCancelledOpenClearsTheViewsToo() {
    MainWindow window;
    window.show();
    QSignalSpy shown(&window, &MainWindow::resultShown);
    QSignalSpy failed(&window, &MainWindow::failureShown);
    QSignalSpy cancelled(&window, &MainWindow::cancelShown);
    window.openScan(CLEARWAY_SAMPLES_DIR "/garage.pcd");
    QVERIFY(shown.wait(kTimeoutMs));
    window.openScan(CLEARWAY_SAMPLES_DIR "/hallway.pcd");
    window.session()->cancel();
    QTRY_VERIFY_WITH_TIMEOUT(cancelled.count() + shown.count() > 1, kTimeoutMs);
    QCOMPARE(failed.count(), 0);  // the operator asked: no error dialog
    QVERIFY(window.findChildren<QMessageBox*>("errorDialog").isEmpty());
    if (cancelled.count() > 0) {  // cancelled in time: nothing shown
      QVERIFY(!window.mapView()->hasResult());
      QVERIFY(window.windowTitle().contains("no scan"));
      QVERIFY(window.statusBar()->currentMessage().contains("Cancelled"));
    } else {  // finished first: the hallway, named in the title
      QVERIFY(window.windowTitle().contains("hallway.pcd"));
    }
  }

  // Defect 2: an acquisition marks the shown map as the previous scan, the first acquisition shows
  // its growing cloud, the scan's time and age are shown, the progress bar ends reset.
  void anAcquisitionGreysThePreviousMapAndShowsTheNewCloud() {
    MainWindow window;
    window.show();
    QSignalSpy shown(&window, &MainWindow::resultShown);
    window.openScan(CLEARWAY_SAMPLES_DIR "/garage.pcd");
    QVERIFY(shown.wait(kTimeoutMs));
    // The sample has no acquisition record: its file's time is when it was saved, not taken.
    QVERIFY(window.findChild<QLabel*>("scanAge")->text().contains("Scan file saved"));
    QVERIFY(!window.mapView()->isStale());
    HardwarePanel* panel = window.hardwarePanel();
    panel->setScanFolder(directory_.filePath("acquired"));
    panel->setSpeedup(400);
    auto* scan_button = window.findChild<QPushButton*>("scanButton");
    panel->connectScanner();
    QTRY_VERIFY_WITH_TIMEOUT(scan_button->isEnabled(), kTimeoutMs);
    QSignalSpy arriving(panel, &HardwarePanel::linesArrived);
    QSignalSpy saved(panel, &HardwarePanel::scanSaved);
    scan_button->click();
    // At once: the map is the previous scan, greyed, with its age.
    QVERIFY(window.shownIsPrevious());
    QVERIFY(window.mapView()->isStale());
    QVERIFY(arriving.wait(kTimeoutMs));
    // The first acquisition's cloud reaches the 3D view as it grows.
    const auto latest = arriving.last().at(0).value<std::shared_ptr<const clearway::Scan>>();
    QCOMPARE(window.sceneView()->shownScan(), latest);
    QVERIFY(saved.count() == 1 || saved.wait(kTimeoutMs));
    QVERIFY(shown.wait(kTimeoutMs));
    QVERIFY(!window.shownIsPrevious());
    QVERIFY(!window.mapView()->isStale());
    QVERIFY(window.windowTitle().contains("rosi-"));
    auto* bar = window.findChild<QProgressBar*>("scanProgress");
    QVERIFY2(bar->value() <= bar->minimum(),
             qPrintable(QString("scan progress still at %1").arg(bar->value())));
  }

  // An acquisition cancelled halfway keeps its lines and shows them: the banner says the scan is
  // partial, or its map reads as the whole place.
  void aCancelledAcquisitionIsShownAsAPartialScan() {
    MainWindow window;
    window.show();
    QSignalSpy shown(&window, &MainWindow::resultShown);
    HardwarePanel* panel = window.hardwarePanel();
    panel->setScanFolder(directory_.filePath("acquired-partial"));
    panel->setSpeedup(2);  // ~75 lines/s: slow enough to cancel halfway
    auto* scan_button = window.findChild<QPushButton*>("scanButton");
    panel->connectScanner();
    QTRY_VERIFY_WITH_TIMEOUT(scan_button->isEnabled(), kTimeoutMs);
    QSignalSpy saved(panel, &HardwarePanel::scanSaved);
    QSignalSpy arriving(panel, &HardwarePanel::linesArrived);
    scan_button->click();
    QTRY_VERIFY_WITH_TIMEOUT(arriving.count() >= 4, kTimeoutMs);
    panel->cancelScan();
    QVERIFY(saved.count() == 1 || saved.wait(kTimeoutMs));
    QCOMPARE(saved.first().at(1).toBool(), false);
    QVERIFY(shown.wait(kTimeoutMs));
    auto* banner = window.findChild<QLabel*>("trustBanner");
    QVERIFY(banner->isVisible());
    QVERIFY2(banner->text().contains("Partial scan"), qPrintable(banner->text()));
  }

  // A robot changed while a new scan was acquired re-ran the previous scan and showed its map in
  // full colour, "done", with green; "Can it get there?" then planned on it. The previous scan
  // stays greyed whatever is re-run on it, and refuses goals, until the new scan is shown.
  void aRobotChangedDuringAnAcquisitionKeepsThePreviousMapGrey() {
    MainWindow window;
    window.show();
    QSignalSpy shown(&window, &MainWindow::resultShown);
    window.openScan(CLEARWAY_SAMPLES_DIR "/garage.pcd");
    QVERIFY(shown.wait(kTimeoutMs));
    const auto previous_scan = window.shownResult().scan;
    HardwarePanel* panel = window.hardwarePanel();
    panel->setScanFolder(directory_.filePath("acquired-robot"));
    panel->setSpeedup(4);  // 4,000 lines at 37.5 a second, four times over: half a minute
    window.findChild<QSpinBox*>("scanLines")->setValue(4000);
    auto* scan_button = window.findChild<QPushButton*>("scanButton");
    panel->connectScanner();
    QTRY_VERIFY_WITH_TIMEOUT(scan_button->isEnabled(), kTimeoutMs);
    QSignalSpy saved(panel, &HardwarePanel::scanSaved);
    scan_button->click();
    QVERIFY(window.shownIsPrevious());
    window.findChild<QDoubleSpinBox*>("robot_width_spin")->setValue(0.7);
    QVERIFY(shown.wait(kTimeoutMs));  // the previous scan re-run for the new robot
    QCOMPARE(window.shownResult().scan, previous_scan);
    QCOMPARE(window.shownResult().result->robot.width, 0.7);
    QVERIFY(window.shownIsPrevious());
    QVERIFY(window.mapView()->isStale());
    const QString answer = window.canItGetThere(1.0, 0.0);
    QVERIFY2(answer.contains("Not on this map"), qPrintable(answer));
    QVERIFY(window.mapView()->path().empty());
    // Cancelled, the part acquired is saved and shown: the latest scan, no longer greyed.
    panel->cancelScan();
    QVERIFY(saved.count() == 1 || saved.wait(kTimeoutMs));
    QTRY_VERIFY_WITH_TIMEOUT(window.shownResult().scan != previous_scan, kTimeoutMs);
    QVERIFY(!window.shownIsPrevious());
    QVERIFY(!window.mapView()->isStale());
  }

  // A goal and its path stayed drawn on the next scan of the same place (an acquisition's), though
  // the answer was dropped.
  void aGoalLeavesWithItsScan() {
    MainWindow window;
    window.show();
    QSignalSpy shown(&window, &MainWindow::resultShown);
    window.openScan(CLEARWAY_SAMPLES_DIR "/garage.pcd");
    QVERIFY(shown.wait(kTimeoutMs));
    // The reachable cell farthest from where the robot stands.
    const clearway::TraversabilityMap& map = window.shownResult().result->map;
    QPointF goal;
    double farthest = 0.0;
    for (int row = 0; row < map.grid.height; ++row)
      for (int column = 0; column < map.grid.width; ++column) {
        if (!map.reach[map.grid.index(column, row)]) continue;
        const Eigen::Vector2d centre = map.grid.centre(column, row);
        const double distance =
            std::hypot(centre.x() - map.robot_pose.x, centre.y() - map.robot_pose.y);
        if (distance > farthest) {
          farthest = distance;
          goal = QPointF(centre.x(), centre.y());
        }
      }
    QVERIFY(farthest > 1.0);
    QVERIFY(window.canItGetThere(goal.x(), goal.y()).contains("Yes, reachable"));
    QVERIFY(!window.mapView()->path().empty());
    QVERIFY(window.mapView()->goal().has_value());
    // The answer held the status bar and hid the hover readout wherever the cursor went: the
    // readout now shows, the answer carried on in it.
    emit window.mapView()->hovered(goal.x(), goal.y(), "traversable");
    const QString readout = window.findChild<QLabel*>("hoverText")->text();
    QVERIFY2(readout.contains("traversable") && readout.contains("Yes, reachable"),
             qPrintable(readout));
    QVERIFY(window.statusBar()->currentMessage().isEmpty());
    // The same place scanned again (as an acquisition saves it): a new scan on the same grid.
    const QString again = directory_.filePath("garage-again.pcd");
    QFile::remove(again);
    QVERIFY(QFile::copy(CLEARWAY_SAMPLES_DIR "/garage.pcd", again));
    window.openScan(again);
    QVERIFY(shown.wait(kTimeoutMs));
    QVERIFY(window.windowTitle().contains("garage-again.pcd"));
    QVERIFY(window.mapView()->path().empty());
    QVERIFY(!window.mapView()->goal().has_value());
  }

  // Defect 3: at the sliders' ends the engine accepts the robot: no error, a new map, "custom".
  void theRobotPanelOffersOnlyWhatTheEngineAccepts() {
    MainWindow window;
    window.show();
    QSignalSpy shown(&window, &MainWindow::resultShown);
    QSignalSpy failed(&window, &MainWindow::failureShown);
    window.openScan(CLEARWAY_SAMPLES_DIR "/garage.pcd");
    QVERIFY(shown.wait(kTimeoutMs));
    RobotPanel* robot = window.robotPanel();
    for (const char* key : {"robot_width", "robot_length", "robot_height", "robot_max_step"}) {
      auto* slider = window.findChild<QSlider*>(QString(key) + "_slider");
      QVERIFY(slider);
      for (const int end : {slider->minimum(), slider->maximum()}) {
        slider->setValue(end);
        clearway::SegmentationParams params = window.session()->params();
        params.robot = robot->robot();
        QVERIFY2(params.validate().empty(), qPrintable(QString("%1 at %2").arg(key).arg(end)));
      }
    }
    auto* width = window.findChild<QSlider*>("robot_width_slider");
    width->setValue(width->minimum());
    QVERIFY(shown.wait(kTimeoutMs));
    QCOMPARE(failed.count(), 0);
    QCOMPARE(robot->presetName(), QString("custom"));
    QVERIFY(window.windowTitle().contains("custom"));
  }

  // A robot asked for from the command line is shown as given or refused with the reason: the
  // panel's boxes would have changed a 100 m width to 4 m, and a 0.05 m height to 0.11 m, silently
  // (the map was of a robot nobody asked for), and a changed preset kept the preset's name.
  void aRobotFromOutsideIsShownAsGivenOrRefused() {
    MainWindow window;
    RobotPanel* panel = window.robotPanel();
    const clearway::RobotParams before = panel->robot();
    clearway::RobotParams huge = before;
    huge.width = 100.0;
    const std::string too_wide = panel->takeRobot(huge);
    QVERIFY2(too_wide.find("robot.width") != std::string::npos, too_wide.c_str());
    QCOMPARE(panel->robot().width, before.width);
    clearway::RobotParams flat = before;
    flat.height = 0.05;
    const std::string too_low = panel->takeRobot(flat);
    QVERIFY2(too_low.find("max_step") != std::string::npos, too_low.c_str());
    QCOMPARE(panel->robot().height, before.height);
    clearway::RobotParams wide = before;  // still named as the preset
    wide.width = 0.9;
    wide.length = 0.5;
    QCOMPARE(QString::fromStdString(panel->takeRobot(wide)), QString());
    QCOMPARE(panel->robot().width, 0.9);
    QCOMPARE(panel->robot().length, 0.5);
    QCOMPARE(panel->presetName(), QString("custom"));
    QCOMPARE(QString::fromStdString(panel->robot().name), QString("custom"));
  }

  // Defect 7: fits 1366x768 at first start, remembers its layout, View menu and shortcuts.
  void theWindowFitsASmallScreenAndRemembersItsLayout() {
    {
      MainWindow window;
      window.show();
      const QSize minimum = window.minimumSizeHint();
      QVERIFY2(minimum.width() <= 1366 && minimum.height() <= 740,
               qPrintable(QString("needs %1x%2").arg(minimum.width()).arg(minimum.height())));
      window.resize(1366, 740);
      QTest::qWait(50);
      QVERIFY(window.statusBar()->isVisible());
      QVERIFY(window.statusBar()->geometry().bottom() < window.height());
      auto* robot_dock = window.findChild<QDockWidget*>("robotDock");
      QVERIFY(robot_dock->geometry().bottom() < window.statusBar()->geometry().top());
      robot_dock->hide();
      window.resize(1000, 700);
      window.close();
    }
    MainWindow again;
    again.show();
    QTest::qWait(50);
    QVERIFY(!again.findChild<QDockWidget*>("robotDock")->isVisible());
    QCOMPARE(again.size(), QSize(1000, 700));
    // The View menu brings a closed panel back.
    QMenu* view = again.findChild<QMenu*>("viewMenu");
    QVERIFY(view);
    bool robot_toggle = false;
    for (QAction* action : again.findChildren<QAction*>())
      if (action->text() == "Robot" && action->isCheckable()) {
        robot_toggle = true;
        action->trigger();
      }
    QVERIFY(robot_toggle);
    QVERIFY(again.findChild<QDockWidget*>("robotDock")->isVisible());
  }

  // A field laptop's 1024 x 600 screen: the window fits it, and every control of the side panels
  // (each scanner device's fields too) is on screen or brought there by scrolling its panel,
  // with a scan shown and a long readout in the status bar.
  void everyControlCanBeReachedAt1024x600() {
    MainWindow window;
    window.resize(1024, 600);
    window.show();
    QVERIFY(QTest::qWaitForWindowExposed(&window));
    const QSize minimum = window.minimumSizeHint();
    QVERIFY2(minimum.width() <= 1024 && minimum.height() <= 600,
             qPrintable(QString("needs %1x%2").arg(minimum.width()).arg(minimum.height())));
    QSignalSpy shown(&window, &MainWindow::resultShown);
    window.openScan(CLEARWAY_SAMPLES_DIR "/garage.pcd");
    QVERIFY(shown.wait(kTimeoutMs));
    emit window.mapView()->hovered(
        1.25, -0.5,
        "traversable, fits, but cannot get there: its box meets something in every heading there");
    QTest::qWait(50);
    QCOMPARE(window.size(), QSize(1024, 600));
    auto* device = window.findChild<QComboBox*>("scannerDevice");
    QStringList unreachable;
    for (const char* name : {"robotDock", "scanDock", "hardwareDock"}) {
      auto* dock = window.findChild<QDockWidget*>(name);
      dock->raise();
      for (int page = 0; page < (dock->objectName() == "hardwareDock" ? device->count() : 1);
           ++page) {
        if (dock->objectName() == "hardwareDock") device->setCurrentIndex(page);
        QTest::qWait(50);  // laid out again
        unreachable << unreachableControls(dock->widget(), &window);
      }
    }
    QVERIFY2(unreachable.isEmpty(), qPrintable(unreachable.join("\n")));
  }

  // At 1024 x 600 the Scanner panel was wider than its dock (its longest device name set the box's
  // width): it scrolled sideways as well as up and down, and every device's fields took the
  // serial RoSi's height. The robot panel, the one worked most, showed four of its six rows. No
  // side panel scrolls sideways now, for any device, and the robot panel is whole.
  void theSidePanelsFit1024x600WithoutScrollingSideways() {
    MainWindow window;
    window.resize(1024, 600);
    window.show();
    QVERIFY(QTest::qWaitForWindowExposed(&window));
    auto* device = window.findChild<QComboBox*>("scannerDevice");
    QStringList sideways;
    for (const char* name : {"robotDock", "scanDock", "hardwareDock"}) {
      auto* dock = window.findChild<QDockWidget*>(name);
      dock->raise();
      auto* scroll = qobject_cast<QScrollArea*>(dock->widget());
      QVERIFY(scroll);
      const int pages = dock->objectName() == "hardwareDock" ? device->count() : 1;
      for (int page = 0; page < pages; ++page) {
        if (pages > 1) device->setCurrentIndex(page);
        QTest::qWait(50);  // laid out again
        if (scroll->horizontalScrollBar()->maximum() > 0)
          sideways << QString("%1, page %2: %3 px of panel in %4 px")
                          .arg(name)
                          .arg(page)
                          .arg(scroll->widget()->width())
                          .arg(scroll->viewport()->width());
      }
    }
    QVERIFY2(sideways.isEmpty(), qPrintable(sideways.join("; ")));
    auto* robot = qobject_cast<QScrollArea*>(window.findChild<QDockWidget*>("robotDock")->widget());
    QVERIFY2(robot->verticalScrollBar()->maximum() == 0,
             qPrintable(QString("robot panel %1 px high in %2 px")
                            .arg(robot->widget()->height())
                            .arg(robot->viewport()->height())));
  }

  // The Parameters dialog was 640 px high: on a 600 px screen OK and Cancel lay below its edge.
  void theParametersDialogFitsASmallScreen() {
    MainWindow window;
    window.show();
    ParametersDialog dialog(clearway::SegmentationParams{}, &window);
    dialog.show();
    QVERIFY(QTest::qWaitForWindowExposed(&dialog));
    const QRect screen = dialog.screen()->availableGeometry();
    QVERIFY2(dialog.frameGeometry().height() <= screen.height() &&
                 dialog.frameGeometry().width() <= screen.width(),
             qPrintable(QString("%1x%2 on a %3x%4 screen")
                            .arg(dialog.frameGeometry().width())
                            .arg(dialog.frameGeometry().height())
                            .arg(screen.width())
                            .arg(screen.height())));
    auto* buttons = dialog.findChild<QDialogButtonBox*>();
    QVERIFY(buttons && fullyShown(buttons, &dialog));
  }

  void everyOperatorActionHasAShortcut() {
    MainWindow window;
    QStringList keys;
    for (QAction* action : window.findChildren<QAction*>())
      if (!action->shortcut().isEmpty()) keys << action->shortcut().toString();
    for (const char* expected :
         {"Ctrl+1", "Ctrl+2", "Ctrl+3", "Ctrl+4", "Ctrl+Shift+1", "Ctrl+Shift+5", "F5", "Esc",
          "PgUp", "PgDown", "]", "[", "F", "M", "Ctrl+O"})
      QVERIFY2(keys.contains(expected),
               qPrintable(QString(expected) + " missing from " + keys.join(' ')));
  }

  void theWidthShortcutsChangeTheRobot() {
    MainWindow window;
    const double before = window.robotPanel()->robot().width;
    for (QAction* action : window.findChildren<QAction*>())
      if (action->shortcut() == QKeySequence(Qt::Key_BracketRight)) action->trigger();
    QCOMPARE(window.robotPanel()->robot().width, before + 0.05);
  }

  // Defect 8: max slope re-segments the scan in memory (same scan, camera kept), no reload.
  void changingMaxSlopeDoesNotReloadTheFile() {
    MainWindow window;
    window.show();
    QSignalSpy ready(window.session(), &SegmentationSession::resultReady);
    window.openScan(CLEARWAY_SAMPLES_DIR "/hallway.pcd");
    QVERIFY(ready.wait(kTimeoutMs));
    const auto first = ready.takeFirst().at(0).value<SessionResult>();
    window.findChild<QDoubleSpinBox*>("ground_max_slope_deg_spin")->setValue(5);
    QVERIFY(ready.wait(kTimeoutMs));
    const auto second = ready.takeLast().at(0).value<SessionResult>();
    QCOMPARE(second.scan, first.scan);  // the same scan in memory, not a new load
    QCOMPARE(second.result->analysis->ground_found, true);
  }

  void exportsGetTheirExtensionAndSaySo() {
    MainWindow window;
    window.show();
    QSignalSpy shown(&window, &MainWindow::resultShown);
    window.openScan(CLEARWAY_SAMPLES_DIR "/garage.pcd");
    QVERIFY(shown.wait(kTimeoutMs));
    QSignalSpy exported(&window, &MainWindow::exported);
    MapPictureOptions picture;
    picture.pixels_per_metre = 50;
    QCOMPARE(window.exportTo(ExportKind::kMapPicture, directory_.filePath("garage-map"), picture),
             QString());
    const QString file = directory_.filePath("garage-map.png");
    QCOMPARE(exported.count(), 1);
    QCOMPARE(exported.takeFirst().at(0).toString(), file);
    QVERIFY(window.statusBar()->currentMessage().contains("garage-map.png"));
    const QImage image(file);
    // At 50 px/m the 12 m garage map is far larger than one pixel per 5 cm cell.
    const auto& grid = window.mapView()->image();
    QVERIFY2(image.width() > 2 * grid.width(),
             qPrintable(QString("%1 vs %2").arg(image.width()).arg(grid.width())));
    QCOMPARE(window.exportTo(ExportKind::kReportJson, directory_.filePath("report"), {}),
             QString());
    QVERIFY(QFileInfo::exists(directory_.filePath("report.json")));
  }

  void theParametersAreNamedInWordsWithUnitsPerStage() {
    ParametersDialog dialog(clearway::SegmentationParams{});
    auto* label = dialog.findChild<QLabel*>("lines_max_deviation_label");
    QVERIFY(label);
    QVERIFY(!label->text().contains("lines."));
    QVERIFY(label->text().contains("[m]"));
    QVERIFY(dialog.findChild<QGroupBox*>("group_lines"));
    QVERIFY(dialog.findChild<QGroupBox*>("group_map"));
  }

  // A copied scan's file time is the copy's: when acquisition recorded the time in the pose
  // sidecar, that is when the scan was taken.
  void theScanTimeIsTheAcquisitionsRecordNotTheFilesTime() {
    const QString scan = directory_.filePath("recorded.pcd");
    QFile::remove(scan);
    QVERIFY(QFile::copy(CLEARWAY_SAMPLES_DIR "/garage.pcd", scan));
    const clearway::Scan loaded = clearway::loadScan(scan.toStdString());
    QVERIFY(loaded.sensor_pose.has_value());
    const QString sidecar = directory_.filePath("recorded.pose.json");
    clearway::writePoseSidecar(*loaded.sensor_pose, "arm", sidecar.toStdString());
    QFile file(sidecar);
    QVERIFY(file.open(QIODevice::ReadOnly));
    QJsonObject json = QJsonDocument::fromJson(file.readAll()).object();
    file.close();
    json.insert("time", "2021-03-04T05:06:07Z");
    QVERIFY(file.open(QIODevice::WriteOnly | QIODevice::Truncate));
    file.write(QJsonDocument(json).toJson());
    file.close();

    MainWindow window;
    window.show();
    QSignalSpy shown(&window, &MainWindow::resultShown);
    window.openScan(scan);
    QVERIFY(shown.wait(kTimeoutMs));
    const QDateTime taken = QDateTime::fromString("2021-03-04T05:06:07Z", Qt::ISODate);
    const QString summary = window.findChild<QLabel*>("scanInfo")->text();
    QVERIFY2(
        summary.contains("Taken " + QLocale().toString(taken.toLocalTime(), QLocale::ShortFormat)),
        qPrintable(summary));
    QVERIFY(window.findChild<QLabel*>("scanAge")->text().contains("Scan taken"));
  }

  void theScanPanelSpeaksInWordsWithDetailsBehindAToggle() {
    MainWindow window;
    window.show();
    QSignalSpy shown(&window, &MainWindow::resultShown);
    window.openScan(CLEARWAY_SAMPLES_DIR "/garage.pcd");
    QVERIFY(shown.wait(kTimeoutMs));
    const QString summary = window.findChild<QLabel*>("scanInfo")->text();
    QVERIFY(summary.contains("scan lines"));
    QVERIFY(summary.contains("File saved"));
    auto* details = window.findChild<QLabel*>("scanDetails");
    QVERIFY(!details->isVisible());
    window.findChild<QToolButton*>("scanDetailsToggle")->click();
    QVERIFY(details->isVisible());
    QVERIFY(details->text().contains("total"));
    // No per-stage timings in the status bar.
    QVERIFY(!window.findChild<QLabel*>("timings"));
  }

 private:
  QTemporaryDir directory_;
};

QTEST_MAIN(ConsoleTruthTest)
#include "console_truth_test.moc"
