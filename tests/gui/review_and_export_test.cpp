// Scan review (recent list, Previous/Next, drag and drop), exports and the parameters dialog,
// under QT_QPA_PLATFORM=offscreen with isolated settings.

#include <QComboBox>
#include <QDialogButtonBox>
#include <QDoubleSpinBox>
#include <QFile>
#include <QLabel>
#include <QLineEdit>
#include <QListWidget>
#include <QMessageBox>
#include <QMimeData>
#include <QPushButton>
#include <QSettings>
#include <QSignalSpy>
#include <QSpinBox>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QtTest>

#include "clearway/hardware/rosi_emulator.h"
#include "clearway/io/scan_io.h"
#include "clearway/sim/builtin_scenes.h"
#include "clearway/sim/rosi_simulator.h"
#include "clearway/ui/export_actions.h"
#include "clearway/ui/hardware_panel.h"
#include "clearway/ui/main_window.h"
#include "clearway/ui/parameters_dialog.h"
#include "clearway/ui/scan_panel.h"
#include "clearway/ui/segmentation_session.h"

using namespace clearway::ui;

Q_DECLARE_METATYPE(std::shared_ptr<const clearway::Scan>)

namespace {

constexpr int kTimeoutMs = 30000;

void simulateInto(const QString& path, const std::string& scene_name) {
  const clearway::sim::Scene scene = *clearway::sim::builtinScene(scene_name);
  clearway::sim::SensorModel sensor;
  sensor.lines = 120;
  clearway::saveRosiPcd(
      clearway::sim::simulateRosi(scene, sensor, clearway::sim::defaultPlacement(scene)).scan,
      path.toStdString());
}

// What a scan file holds when it is damaged: a PCD header promising a million points, then none.
void writeCorruptScan(const QString& path) {
  QFile file(path);
  QVERIFY(file.open(QIODevice::WriteOnly | QIODevice::Truncate));
  file.write(
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1000000\nHEIGHT 1\nDATA "
      "binary\nxx");
}

void closeErrorDialogs(QWidget& window) {
  for (auto* dialog : window.findChildren<QMessageBox*>("errorDialog"))
    dialog->close();
}

}  // namespace

class ReviewAndExportTest : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase() {
    // Settings of their own, empty: nothing from other tests or earlier runs.
    QStandardPaths::setTestModeEnabled(true);
    QCoreApplication::setApplicationName("clearway-review-test");
    QSettings().clear();
    qRegisterMetaType<std::shared_ptr<const clearway::Scan>>();
    QVERIFY(directory_.isValid());
    simulateInto(directory_.filePath("a_garage.pcd"), "garage");
    simulateInto(directory_.filePath("b_hallway.pcd"), "hallway");
    // A note beside the scans, as the real-data folders have: Next must not offer it.
    QFile note(directory_.filePath("c_SOURCE.txt"));
    QVERIFY(note.open(QIODevice::WriteOnly));
    note.write("Source: the simulator's garage and hallway.\n");
  }

  // Each test starts with no recent scans.
  void init() { QSettings().clear(); }

  void nextAndPreviousWalkTheFolderAndTheRecentListRemembers() {
    MainWindow window;
    window.show();
    QSignalSpy shown(&window, &MainWindow::resultShown);
    window.openScan(directory_.filePath("a_garage.pcd"));
    QVERIFY(shown.wait(kTimeoutMs));
    auto* next = window.findChild<QPushButton*>("nextScanButton");
    auto* previous = window.findChild<QPushButton*>("previousScanButton");
    QVERIFY(next->isEnabled());
    QVERIFY(!previous->isEnabled());
    next->click();
    QVERIFY(shown.wait(kTimeoutMs));
    QVERIFY(previous->isEnabled());
    QVERIFY(!next->isEnabled());
    const auto* recent = window.findChild<QListWidget*>("recentScans");
    QCOMPARE(recent->count(), 2);
    QVERIFY(recent->item(0)->text().endsWith("b_hallway.pcd"));
    QCOMPARE(ScanPanel::scansInFolder(directory_.path()).size(), 2);
  }

  // A scan that failed to open is where the operator stands in its folder: Next went back to it
  // (Next re-opened the same broken file from the scan shown before, again and again) and
  // Previous could not reach the scan before it. It is not put in the recent list as opened, and
  // a recent entry that no longer opens says so.
  void nextAndPreviousMoveOnFromAScanThatFailedToOpen() {
    QTemporaryDir folder;
    QVERIFY(folder.isValid());
    QVERIFY(QFile::copy(directory_.filePath("a_garage.pcd"), folder.filePath("a_garage.pcd")));
    writeCorruptScan(folder.filePath("b_broken.pcd"));
    QVERIFY(QFile::copy(directory_.filePath("b_hallway.pcd"), folder.filePath("c_hallway.pcd")));
    MainWindow window;
    window.show();
    QSignalSpy shown(&window, &MainWindow::resultShown);
    QSignalSpy failed(&window, &MainWindow::failureShown);
    auto* next = window.findChild<QPushButton*>("nextScanButton");
    auto* previous = window.findChild<QPushButton*>("previousScanButton");
    auto* recent = window.findChild<QListWidget*>("recentScans");
    window.openScan(folder.filePath("a_garage.pcd"));
    QVERIFY(shown.wait(kTimeoutMs));
    next->click();
    QVERIFY(failed.wait(kTimeoutMs));
    closeErrorDialogs(window);
    QVERIFY(failed.takeFirst().at(0).toString().contains("b_broken.pcd"));
    // The recent list names what opened, the broken file not among it.
    QCOMPARE(recent->count(), 1);
    QVERIFY(recent->item(0)->text().endsWith("a_garage.pcd"));
    // Next moves on past the broken file, to the scan after it.
    QVERIFY(next->isEnabled());
    next->click();
    QVERIFY(shown.wait(kTimeoutMs));
    QCOMPARE(failed.count(), 0);
    QVERIFY2(window.windowTitle().contains("c_hallway.pcd"), qPrintable(window.windowTitle()));
    // Back through it: Previous goes to the broken file, then on to the one before it.
    previous->click();
    QVERIFY(failed.wait(kTimeoutMs));
    closeErrorDialogs(window);
    QVERIFY(previous->isEnabled());
    previous->click();
    QVERIFY(shown.wait(kTimeoutMs));
    QVERIFY2(window.windowTitle().contains("a_garage.pcd"), qPrintable(window.windowTitle()));
    // A scan in the recent list that no longer opens stays where it was, marked, and opens from
    // the list again once it is mended.
    writeCorruptScan(folder.filePath("c_hallway.pcd"));
    QCOMPARE(recent->count(), 2);
    QListWidgetItem* hallway = recent->item(1);
    QVERIFY(hallway->text().endsWith("c_hallway.pcd"));
    emit recent->itemActivated(hallway);
    QVERIFY(failed.wait(kTimeoutMs));
    closeErrorDialogs(window);
    QVERIFY(window.findChild<QLabel*>("scanInfo")->text().contains("c_hallway.pcd"));
    QVERIFY(recent->item(0)->text().endsWith("a_garage.pcd"));
    QVERIFY2(recent->item(1)->text().contains("could not be opened"),
             qPrintable(recent->item(1)->text()));
    QFile::remove(folder.filePath("c_hallway.pcd"));
    QVERIFY(QFile::copy(directory_.filePath("b_hallway.pcd"), folder.filePath("c_hallway.pcd")));
    emit recent->itemActivated(recent->item(1));
    QVERIFY(shown.wait(kTimeoutMs));
    QVERIFY(window.windowTitle().contains("c_hallway.pcd"));
    QVERIFY(recent->item(0)->text().endsWith("c_hallway.pcd"));
    QVERIFY(!recent->item(1)->text().contains("could not be opened"));
  }

  void droppingAScanOpensIt() {
    MainWindow window;
    window.show();
    QSignalSpy shown(&window, &MainWindow::resultShown);
    QMimeData data;
    data.setUrls({QUrl::fromLocalFile(directory_.filePath("a_garage.pcd"))});
    QDragEnterEvent enter(QPoint(10, 10), Qt::CopyAction, &data, Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(&window, &enter);
    QVERIFY(enter.isAccepted());
    QDropEvent drop(QPointF(10, 10), Qt::CopyAction, &data, Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(&window, &drop);
    QVERIFY(shown.wait(kTimeoutMs));
  }

  void exportsWriteEveryFileAndSayWhyWhenTheyCannot() {
    SegmentationSession session;
    QSignalSpy ready(&session, &SegmentationSession::resultReady);
    session.openScan(directory_.filePath("a_garage.pcd"));
    QVERIFY(ready.wait(kTimeoutMs));
    const auto result = ready.takeFirst().at(0).value<SessionResult>();
    const std::pair<ExportKind, QString> kinds[] = {{ExportKind::kMapPng, "map.png"},
                                                    {ExportKind::kRosMap, "ros.pgm"},
                                                    {ExportKind::kScenePly, "scene.ply"},
                                                    {ExportKind::kReportJson, "report.json"}};
    for (const auto& [kind, name] : kinds) {
      const QString path = directory_.filePath(name);
      QCOMPARE(exportResult(kind, result, session.params(), path, nullptr), QString());
      QVERIFY2(QFileInfo(path).size() > 100, qPrintable(name));
    }
    QVERIFY(QFileInfo::exists(directory_.filePath("ros.yaml")));
    // No 3D view offscreen: a reason, not a crash or an empty file.
    QVERIFY(!exportResult(ExportKind::kScreenshot3d, result, session.params(),
                          directory_.filePath("3d.png"), nullptr)
                 .isEmpty());
    QVERIFY(!exportResult(ExportKind::kMapPng, SessionResult{}, session.params(),
                          directory_.filePath("x.png"), nullptr)
                 .isEmpty());
  }

  void theParametersDialogRefusesValuesThatCannotWork() {
    ParametersDialog dialog(clearway::SegmentationParams{});
    QVERIFY(dialog.problems().isEmpty());
    auto* ok = dialog.findChild<QDialogButtonBox*>()->button(QDialogButtonBox::Ok);
    QVERIFY(ok->isEnabled());
    // Cells a quarter of the robot wide cannot resolve it.
    dialog.findChild<QDoubleSpinBox*>("map_resolution")->setValue(0.5);
    QVERIFY(!dialog.problems().isEmpty());
    QVERIFY(!ok->isEnabled());
    QVERIFY(dialog.findChild<QLabel*>("parameterProblems")->text().contains("map.resolution"));
    dialog.findChild<QDoubleSpinBox*>("map_resolution")->setValue(0.05);
    dialog.findChild<QDoubleSpinBox*>("robot_width")->setValue(1.1);
    QVERIFY(ok->isEnabled());
    QCOMPARE(dialog.params().robot.width, 1.1);
  }

  void scanAndStopSavesTheScanThenShowsTheResult() {
    MainWindow window;
    window.show();
    HardwarePanel* panel = window.hardwarePanel();
    const QString folder = directory_.filePath("acquired");
    panel->setScanFolder(folder);
    panel->setSpeedup(400);
    auto* scan_button = window.findChild<QPushButton*>("scanButton");
    panel->connectScanner();
    QTRY_VERIFY_WITH_TIMEOUT(scan_button->isEnabled(), kTimeoutMs);
    QSignalSpy saved(panel, &HardwarePanel::scanSaved);
    QSignalSpy shown(&window, &MainWindow::resultShown);
    QSignalSpy arriving(panel, &HardwarePanel::linesArrived);
    scan_button->click();
    QVERIFY(saved.wait(kTimeoutMs));
    // The cloud grew while the lines came in.
    QVERIFY(arriving.count() > 2);
    const auto first = arriving.first().at(0).value<std::shared_ptr<const clearway::Scan>>();
    const auto last = arriving.last().at(0).value<std::shared_ptr<const clearway::Scan>>();
    QVERIFY(first && last);
    QVERIFY(last->lines.size() > first->lines.size());
    const QString path = saved.takeFirst().at(0).toString();
    QVERIFY(QFileInfo::exists(path));
    QVERIFY(path.startsWith(folder));
    QVERIFY(shown.wait(kTimeoutMs));
    QCOMPARE(shown.takeFirst().at(0).toBool(), true);
  }

  void cancellingAScanKeepsWhatArrived() {
    HardwarePanel panel;
    panel.setScanFolder(directory_.filePath("partial"));
    panel.setSpeedup(2);  // ~75 lines/s: slow enough to cancel halfway
    auto* scan_button = panel.findChild<QPushButton*>("scanButton");
    panel.connectScanner();
    QTRY_VERIFY_WITH_TIMEOUT(scan_button->isEnabled(), kTimeoutMs);
    QSignalSpy saved(&panel, &HardwarePanel::scanSaved);
    scan_button->click();
    QTest::qWait(300);
    panel.cancelScan();
    QVERIFY(saved.count() == 1 || saved.wait(kTimeoutMs));
    const auto arguments = saved.takeFirst();
    QCOMPARE(arguments.at(1).toBool(), false);
    QVERIFY(arguments.at(0).toString().endsWith("-partial.pcd"));
    const clearway::Scan partial = clearway::loadScan(arguments.at(0).toString().toStdString());
    QVERIFY(partial.lines.size() > 0);
    QVERIFY(partial.lines.size() < 300);
  }

  void theSerialRosiAcquiresFromTheEmulatorThroughThePanel() {
    clearway::hardware::RosiEmulator emulator(*clearway::sim::builtinScene("garage"), {20.0, 2});
    HardwarePanel panel;
    panel.setScanFolder(directory_.filePath("serial"));
    panel.findChild<QComboBox*>("scannerDevice")->setCurrentIndex(1);
    panel.findChild<QLineEdit*>("lmsPort")->setText(QString::fromStdString(emulator.lmsPort()));
    panel.findChild<QLineEdit*>("turntablePort")
        ->setText(QString::fromStdString(emulator.turntablePort()));
    panel.findChild<QSpinBox*>("scanLines")->setValue(60);
    auto* link_speed = panel.findChild<QComboBox*>("linkSpeed");
    link_speed->setCurrentIndex(link_speed->findData(500000));
    auto* scan_button = panel.findChild<QPushButton*>("scanButton");
    QSignalSpy status(&panel, &HardwarePanel::statusChanged);
    panel.connectScanner();
    QTRY_VERIFY_WITH_TIMEOUT(scan_button->isEnabled(), kTimeoutMs);
    QSignalSpy saved(&panel, &HardwarePanel::scanSaved);
    scan_button->click();
    QVERIFY(saved.wait(kTimeoutMs));
    const auto arguments = saved.takeFirst();
    QCOMPARE(arguments.at(1).toBool(), true);
    const clearway::Scan scan = clearway::loadScan(arguments.at(0).toString().toStdString());
    QCOMPARE(scan.lines.size(), std::size_t(60));
    QCOMPARE(scan.pointsPerLine(), std::size_t(180));
    bool at_500k = false;
    for (const auto& message : status)
      at_500k |= message.at(0).toString().contains("500000 baud");
    QVERIFY(at_500k);
  }

  void aMissingSerialPortIsNamedInWords() {
    HardwarePanel panel;
    panel.findChild<QComboBox*>("scannerDevice")->setCurrentIndex(1);
    panel.findChild<QLineEdit*>("lmsPort")->setText("/dev/clearway-none");
    QSignalSpy status(&panel, &HardwarePanel::statusChanged);
    panel.connectScanner();
    QTRY_VERIFY_WITH_TIMEOUT(status.count() > 0, kTimeoutMs);
    bool named = false;
    for (const auto& arguments : status)
      named |= arguments.at(0).toString().contains("/dev/clearway-none");
    QVERIFY(named);
  }

 private:
  QTemporaryDir directory_;
};

QTEST_MAIN(ReviewAndExportTest)
#include "review_and_export_test.moc"
