// The Scanner panel (offscreen): each device shows only its own fields, Disconnect, the mounting
// edited and checked, the ground density for the chosen line count, and the arm's pose shown and
// saved beside the acquired scan.

#include <QComboBox>
#include <QDir>
#include <QFile>
#include <QJsonDocument>
#include <QJsonObject>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QRegularExpression>
#include <QSignalSpy>
#include <QSpinBox>
#include <QTemporaryDir>
#include <QtTest>

#include "../support/file_size_limit.h"
#include "clearway/hardware/rosi_emulator.h"
#include "clearway/io/scan_io.h"
#include "clearway/sim/builtin_scenes.h"
#include "clearway/ui/hardware_panel.h"

using clearway::ui::HardwarePanel;

namespace {
constexpr int kTimeoutMs = 30000;

// The panel set to the serial RoSi on the emulator's ports, scans going to `folder`.
void useEmulatorsPorts(HardwarePanel& panel, const clearway::hardware::RosiEmulator& emulator,
                       const QString& folder) {
  panel.setScanFolder(folder);
  panel.findChild<QComboBox*>("scannerDevice")->setCurrentIndex(1);
  panel.findChild<QLineEdit*>("lmsPort")->setText(QString::fromStdString(emulator.lmsPort()));
  panel.findChild<QLineEdit*>("turntablePort")
      ->setText(QString::fromStdString(emulator.turntablePort()));
}
}  // namespace

class HardwarePanelTest : public QObject {
  Q_OBJECT

 private slots:
  void eachDeviceShowsOnlyItsOwnFields() {
    HardwarePanel panel;
    auto* device = panel.findChild<QComboBox*>("scannerDevice");
    const auto visible = [&](const char* name) {
      return panel.findChild<QWidget*>(name)->isVisibleTo(&panel);
    };
    device->setCurrentIndex(0);
    QVERIFY(visible("simulatedScene"));
    for (const char* serial_only : {"lmsPort", "turntablePort", "linkSpeed", "armPort", "mounting"})
      QVERIFY2(!visible(serial_only), serial_only);
    device->setCurrentIndex(1);
    QVERIFY(!visible("simulatedScene"));
    for (const char* serial_only : {"lmsPort", "turntablePort", "linkSpeed", "armPort", "mounting"})
      QVERIFY2(visible(serial_only), serial_only);
  }

  void disconnectReleasesTheDevice() {
    HardwarePanel panel;
    panel.setSpeedup(400);
    auto* scan = panel.findChild<QPushButton*>("scanButton");
    auto* disconnect = panel.findChild<QPushButton*>("disconnectButton");
    auto* connect = panel.findChild<QPushButton*>("connectButton");
    QVERIFY(!disconnect->isEnabled());
    panel.connectScanner();
    QTRY_VERIFY_WITH_TIMEOUT(scan->isEnabled(), kTimeoutMs);
    QVERIFY(disconnect->isEnabled());
    disconnect->click();
    QVERIFY(!scan->isEnabled());
    QVERIFY(!disconnect->isEnabled());
    QVERIFY(connect->isEnabled());
    QCOMPARE(panel.findChild<QLabel*>("scannerStatus")->text(), QString("Disconnected."));
  }

  void aMountingThatIsNoPoseIsRefused() {
    HardwarePanel panel;
    panel.findChild<QComboBox*>("scannerDevice")->setCurrentIndex(1);
    panel.findChild<QLineEdit*>("mounting")->setText("0,0,1");
    panel.connectScanner();
    QVERIFY(panel.findChild<QLabel*>("scannerStatus")->text().contains("not a pose"));
    QVERIFY(!panel.findChild<QPushButton*>("disconnectButton")->isEnabled());
  }

  void theDensityFollowsTheChosenLineCount() {
    HardwarePanel panel;
    auto* lines = panel.findChild<QSpinBox*>("scanLines");
    auto* density = panel.findChild<QLabel*>("groundDensity");
    QVERIFY(density);
    QVERIFY(density->isVisibleTo(&panel));
    // "green possible up to X m": how far from the scanner ground can be vouched for.
    const auto vouched = [&] {
      const QRegularExpressionMatch match =
          QRegularExpression("up to ([0-9.]+) m").match(density->text());
      return match.hasMatch() ? match.captured(1).toDouble() : -1.0;
    };
    // The simulated garage (its scanner 1.2 m high), the default robot (0.1 m step).
    panel.findChild<QComboBox*>("simulatedScene")->setCurrentText("garage");
    lines->setValue(40);
    const double at_40 = vouched();
    lines->setValue(80);
    const double at_80 = vouched();
    lines->setValue(423);
    const double at_423 = vouched();
    QVERIFY2(at_40 > 0.0, qPrintable(density->text()));
    // Across the turn the samples are (distance x 2 pi / lines) apart: twice the lines, twice as
    // far; at 423 lines the 0.5 deg along each line limits it instead (11.5 m).
    // (The readout rounds to 0.1 m.)
    QVERIFY2(std::abs(at_80 - 2.0 * at_40) <= 0.15,
             qPrintable(QString("%1 %2").arg(at_40).arg(at_80)));
    QVERIFY2(at_423 > at_80 && at_423 < 12.0, qPrintable(density->text()));
    // A robot with a smaller step is vouched for nearer.
    panel.setRobotStep(0.05);
    QVERIFY2(vouched() < at_423, qPrintable(density->text()));
  }

  // The simulated RoSi scanned the scene it was connected with, whatever the box said after.
  void aSceneChosenWhileConnectedIsTheOneScanned() {
    QTemporaryDir directory;
    HardwarePanel panel;
    panel.setScanFolder(directory.filePath("simulated"));
    panel.setSpeedup(400);
    panel.findChild<QSpinBox*>("scanLines")->setValue(40);
    auto* scene = panel.findChild<QComboBox*>("simulatedScene");
    scene->setCurrentText("garage");
    auto* scan = panel.findChild<QPushButton*>("scanButton");
    panel.connectScanner();
    QTRY_VERIFY_WITH_TIMEOUT(scan->isEnabled(), kTimeoutMs);
    QSignalSpy status(&panel, &HardwarePanel::statusChanged);
    scene->setCurrentText("hallway");
    QTRY_VERIFY_WITH_TIMEOUT(scan->isEnabled(), kTimeoutMs);
    QSignalSpy saved(&panel, &HardwarePanel::scanSaved);
    scan->click();
    QVERIFY(saved.wait(kTimeoutMs));
    QStringList said;
    for (const QList<QVariant>& signal : status)
      said << signal.at(0).toString();
    QVERIFY2(said.filter("scene hallway): scanning").size() == 1, qPrintable(said.join(" | ")));
    QVERIFY2(said.filter("scene garage): scanning").isEmpty(), qPrintable(said.join(" | ")));
  }

  void theArmsPoseIsShownAndSavedWithTheScan() {
    clearway::hardware::EmulatorOptions options(20.0, 2);
    options.arm_tilt_deg = 30;
    options.arm_roll_deg = 60;
    clearway::hardware::RosiEmulator emulator(*clearway::sim::builtinScene("garage"), options);
    QTemporaryDir directory;
    HardwarePanel panel;
    useEmulatorsPorts(panel, emulator, directory.filePath("serial"));
    panel.findChild<QLineEdit*>("armPort")->setText(QString::fromStdString(emulator.armPort()));
    panel.findChild<QSpinBox*>("scanLines")->setValue(40);
    auto* scan = panel.findChild<QPushButton*>("scanButton");
    panel.connectScanner();
    QTRY_VERIFY_WITH_TIMEOUT(scan->isEnabled(), kTimeoutMs);
    QSignalSpy saved(&panel, &HardwarePanel::scanSaved);
    scan->click();
    QVERIFY(saved.wait(kTimeoutMs));
    const QString arm_pose = panel.findChild<QLabel*>("armPose")->text();
    QVERIFY2(arm_pose.contains("tilt 30.0") && arm_pose.contains("roll 60.0"),
             qPrintable(arm_pose));
    const QString path = saved.first().at(0).toString();
    // The lines were journaled while they came; once the scan is saved the journal is gone.
    QVERIFY(QDir(directory.filePath("serial")).entryList({"*.journal"}).isEmpty());
    QFile sidecar(QString(path).replace(".pcd", ".pose.json"));
    QVERIFY2(sidecar.open(QIODevice::ReadOnly), qPrintable(sidecar.fileName()));
    const QJsonObject json = QJsonDocument::fromJson(sidecar.readAll()).object();
    QCOMPARE(json.value("source").toString(), QString("arm"));
    QVERIFY(std::abs(json.value("arm_tilt_deg").toDouble() - 30.0) < 1e-6);
    const clearway::Scan acquired = clearway::loadScan(path.toStdString());
    QVERIFY(acquired.sensor_pose);
    QVERIFY(std::abs(acquired.sensor_pose->position[2] -
                     emulator.worldFromScanner().translation.z()) < 1e-5);
  }

  // The scans folder's disk fills up mid-scan (here a file size limit on this process: EFBIG, as
  // ENOSPC on a full disk): the panel says so while the scan runs, and when the scan cannot be
  // saved either, that its journal keeps only the lines before it stopped. It said nothing until
  // the end, and then that the journal kept the scan's lines.
  void aJournalThatStopsIsSaidWhileTheScanRuns() {
    clearway::hardware::RosiEmulator emulator(*clearway::sim::builtinScene("garage"), {2.0, 2});
    QTemporaryDir directory;
    HardwarePanel panel;
    useEmulatorsPorts(panel, emulator, directory.filePath("serial"));
    panel.findChild<QSpinBox*>("scanLines")->setValue(300);  // a turn, 4 s
    auto* scan = panel.findChild<QPushButton*>("scanButton");
    panel.connectScanner();
    QTRY_VERIFY_WITH_TIMEOUT(scan->isEnabled(), kTimeoutMs);
    QSignalSpy status(&panel, &HardwarePanel::statusChanged);
    QSignalSpy unsaved(&panel, &HardwarePanel::scanEndedUnsaved);
    const auto said = [&] {
      QStringList all;
      for (const QList<QVariant>& signal : status)
        all << signal.at(0).toString();
      return all.join(" | ");
    };
    clearway::test::FileSizeLimit limit(16 * 1024);  // about 15 lines of the journal
    QVERIFY(limit.ok());
    scan->click();
    QTRY_VERIFY_WITH_TIMEOUT(said().contains("cannot write the journal"), kTimeoutMs);
    const std::uint64_t sent_when_said = emulator.linesSent();
    QVERIFY(unsaved.isEmpty());
    QVERIFY2(sent_when_said < 200, "said once the scan had ended");
    QVERIFY(unsaved.wait(kTimeoutMs));
    limit.lift();
    const QString end = status.last().at(0).toString();
    QVERIFY2(end.contains("could not be saved") && end.contains("File too large") &&
                 end.contains("Only the lines its journal held when it stopped are kept") &&
                 end.contains("the journal holds the first"),
             qPrintable(end));
  }
};

QTEST_MAIN(HardwarePanelTest)
#include "hardware_panel_test.moc"
