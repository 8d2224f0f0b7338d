// The Scanner panel (offscreen): each device shows only its own fields, Disconnect, the mounting
// edited and checked, and the arm's pose shown and saved beside the acquired scan.

#include <QComboBox>
#include <QDir>
#include <QFile>
#include <QJsonDocument>
#include <QJsonObject>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QSignalSpy>
#include <QSpinBox>
#include <QTemporaryDir>
#include <QtTest>

#include "clearway/hardware/rosi_emulator.h"
#include "clearway/io/scan_io.h"
#include "clearway/sim/builtin_scenes.h"
#include "clearway/ui/hardware_panel.h"

using clearway::ui::HardwarePanel;

namespace {
constexpr int kTimeoutMs = 30000;
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

  void theArmsPoseIsShownAndSavedWithTheScan() {
    clearway::hardware::EmulatorOptions options(20.0, 2);
    options.arm_tilt_deg = 30;
    options.arm_roll_deg = 60;
    clearway::hardware::RosiEmulator emulator(*clearway::sim::builtinScene("garage"), options);
    QTemporaryDir directory;
    HardwarePanel panel;
    panel.setScanFolder(directory.filePath("serial"));
    panel.findChild<QComboBox*>("scannerDevice")->setCurrentIndex(1);
    panel.findChild<QLineEdit*>("lmsPort")->setText(QString::fromStdString(emulator.lmsPort()));
    panel.findChild<QLineEdit*>("turntablePort")
        ->setText(QString::fromStdString(emulator.turntablePort()));
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
};

QTEST_MAIN(HardwarePanelTest)
#include "hardware_panel_test.moc"
