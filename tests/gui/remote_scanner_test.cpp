// The Scanner panel's remote RoSi against a real `clearway-cli serve --simulate garage` started by
// the test on 127.0.0.1: connect, the link's state in words, scan, the scan saved whole; and a
// credentials folder without console.json named in the status.

#include <QComboBox>
#include <QDir>
#include <QLabel>
#include <QLineEdit>
#include <QProcess>
#include <QPushButton>
#include <QSignalSpy>
#include <QSpinBox>
#include <QTemporaryDir>
#include <QtTest>

#include "clearway/io/scan_io.h"
#include "clearway/ui/hardware_panel.h"

using clearway::ui::HardwarePanel;

Q_DECLARE_METATYPE(std::shared_ptr<const clearway::Scan>)

namespace {
constexpr int kTimeoutMs = 60000;  // only against hangs
constexpr int kRemoteDevice = 2;
constexpr int kLines = 120;
}  // namespace

class RemoteScannerTest : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase() {
    QStandardPaths::setTestModeEnabled(true);
    qRegisterMetaType<std::shared_ptr<const clearway::Scan>>();
    QVERIFY(directory_.isValid());
    credentials_ = directory_.filePath("credentials");
    QCOMPARE(QProcess::execute(CLEARWAY_CLI, {"serve", "--init-credentials", credentials_}), 0);
    serve_.setProgram(CLEARWAY_CLI);
    serve_.setArguments({"serve", "--credentials", credentials_, "--listen", "127.0.0.1:0",
                         "--simulate", "garage", "--speed", "20", "--storage",
                         directory_.filePath("robot")});
    serve_.setProcessChannelMode(QProcess::SeparateChannels);
    serve_.start();
    QVERIFY(serve_.waitForStarted(kTimeoutMs));
    // serve prints "listening on 127.0.0.1:PORT (...)" once it listens.
    QTRY_VERIFY_WITH_TIMEOUT(serve_.canReadLine() || serve_.waitForReadyRead(100), kTimeoutMs);
    const QString line = QString::fromUtf8(serve_.readLine());
    const QRegularExpressionMatch match =
        QRegularExpression("listening on 127\\.0\\.0\\.1:(\\d+)").match(line);
    QVERIFY2(match.hasMatch(), qPrintable(line));
    port_ = match.captured(1).toInt();
  }

  void cleanupTestCase() {
    serve_.terminate();
    QVERIFY(serve_.waitForFinished(kTimeoutMs));
    QCOMPARE(serve_.exitCode(), 0);
  }

  void scansThroughTheRobotAndShowsTheLinkInWords() {
    HardwarePanel panel;
    panel.setScanFolder(directory_.filePath("console"));
    auto* device = panel.findChild<QComboBox*>("scannerDevice");
    device->setCurrentIndex(kRemoteDevice);
    panel.findChild<QLineEdit*>("remoteHost")->setText("127.0.0.1");
    panel.findChild<QSpinBox*>("remotePort")->setValue(port_);
    panel.findChild<QLineEdit*>("remoteCredentials")->setText(credentials_);
    panel.findChild<QSpinBox*>("scanLines")->setValue(kLines);
    auto* scan_button = panel.findChild<QPushButton*>("scanButton");
    auto* link = panel.findChild<QLabel*>("remoteLink");
    panel.connectScanner();
    QTRY_VERIFY_WITH_TIMEOUT(scan_button->isEnabled(), kTimeoutMs);
    QTRY_VERIFY_WITH_TIMEOUT(link->text().contains("connected to 127.0.0.1"), kTimeoutMs);
    QVERIFY2(link->text().contains("in control"), qPrintable(link->text()));
    QTRY_VERIFY_WITH_TIMEOUT(link->text().contains("round trip"), kTimeoutMs);
    QVERIFY(panel.findChild<QLabel*>("scannerStatus")->text().contains("Remote RoSi"));

    QSignalSpy saved(&panel, &HardwarePanel::scanSaved);
    QSignalSpy arriving(&panel, &HardwarePanel::linesArrived);
    scan_button->click();
    QVERIFY(saved.wait(kTimeoutMs));
    QCOMPARE(saved.first().at(1).toBool(), true);
    QVERIFY(arriving.count() > 2);  // the cloud grew as the lines came
    const clearway::Scan scan = clearway::loadScan(saved.first().at(0).toString().toStdString());
    QCOMPARE(int(scan.lines.size()), kLines);
    QCOMPARE(int(scan.size()), kLines * 180);
    // The robot kept its own copy.
    QCOMPARE(QDir(directory_.filePath("robot")).entryList({"scan-*.pcd"}).size(), 1);
  }

  void aFolderWithoutCredentialsIsNamed() {
    HardwarePanel panel;
    panel.findChild<QComboBox*>("scannerDevice")->setCurrentIndex(kRemoteDevice);
    panel.findChild<QLineEdit*>("remoteCredentials")->setText(directory_.filePath("nowhere"));
    QSignalSpy status(&panel, &HardwarePanel::statusChanged);
    panel.connectScanner();
    QVERIFY(!status.isEmpty());
    const QString text = status.last().at(0).toString();
    QVERIFY2(text.contains("console.json") || text.contains("nowhere"), qPrintable(text));
    QVERIFY(!panel.findChild<QPushButton*>("scanButton")->isEnabled());
  }

 private:
  QTemporaryDir directory_;
  QString credentials_;
  QProcess serve_;
  int port_ = 0;
};

QTEST_MAIN(RemoteScannerTest)
#include "remote_scanner_test.moc"
