// Nothing the operator acquired is lost, in the console: a journal left in the scans folder by an
// acquisition that did not finish is offered at start (File > Recover interrupted acquisitions),
// turned into a scan in the background and opened; a journal that is no journal is named and
// kept. Offscreen; settings and paths isolated (QStandardPaths test mode).

#include <QAction>
#include <QCoreApplication>
#include <QDir>
#include <QFile>
#include <QSettings>
#include <QSignalSpy>
#include <QStandardPaths>
#include <QStatusBar>
#include <QTemporaryDir>
#include <QtTest>

#include "clearway/hardware/rosi_emulator.h"
#include "clearway/hardware/serial_acquisition.h"
#include "clearway/io/scan_io.h"
#include "clearway/sim/builtin_scenes.h"
#include "clearway/ui/hardware_panel.h"
#include "clearway/ui/main_window.h"

using clearway::ui::MainWindow;

namespace {
constexpr int kTimeoutMs = 60000;
constexpr int kLines = 60;
}  // namespace

class JournalRecoveryTest : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase() {
    QStandardPaths::setTestModeEnabled(true);
    QCoreApplication::setApplicationName("clearway-journal-recovery-test");
    QSettings().clear();
  }

  void aLeftJournalIsOfferedRecoveredAndOpened() {
    QTemporaryDir folder;
    QVERIFY(folder.isValid());
    // An acquisition whose console died before saving: its journal is all that is left.
    const QString journal = folder.filePath("rosi-crashed.journal");
    {
      clearway::hardware::RosiEmulator emulator(*clearway::sim::builtinScene("garage"), {20.0, 3});
      clearway::hardware::AcquisitionOptions options;
      options.lines = kLines;
      options.journal = journal.toStdString();
      const auto acquired = clearway::hardware::acquireRosiScan(emulator.lmsPort(),
                                                                emulator.turntablePort(), options);
      QVERIFY2(acquired.complete, acquired.error.c_str());
    }
    QVERIFY(QFile::exists(journal));
    // And a file that only looks like one.
    const QString broken = folder.filePath("rosi-broken.journal");
    {
      QFile file(broken);
      QVERIFY(file.open(QIODevice::WriteOnly));
      file.write("this is not a journal\n");
    }

    MainWindow window;
    auto* action = window.findChild<QAction*>("recoverAction");
    QVERIFY(action);
    window.hardwarePanel()->setScanFolder(folder.path());
    QCOMPARE(window.checkUnfinishedJournals(), 2);
    QVERIFY(action->isEnabled());
    QVERIFY(window.statusBar()->currentMessage().contains("can be recovered"));

    QSignalSpy recovered(&window, &MainWindow::journalsRecovered);
    QSignalSpy shown(&window, &MainWindow::resultShown);
    action->trigger();
    QVERIFY(recovered.wait(kTimeoutMs));
    const QStringList scans = recovered.at(0).at(0).toStringList();
    const QStringList problems = recovered.at(0).at(1).toStringList();
    QCOMPARE(scans.size(), 1);
    QCOMPARE(scans.first(), folder.filePath("rosi-crashed-recovered.pcd"));
    QCOMPARE(int(clearway::loadScan(scans.first().toStdString()).lines.size()), kLines);
    QVERIFY(!QFile::exists(journal));  // recovered: no longer needed
    QCOMPARE(problems.size(), 1);
    QVERIFY2(problems.first().contains("rosi-broken.journal"), qPrintable(problems.first()));
    QVERIFY(QFile::exists(broken));  // never thrown away
    // The recovered scan is opened and shown.
    QVERIFY(shown.count() > 0 || shown.wait(kTimeoutMs));
    QVERIFY(window.windowTitle().contains("rosi-crashed-recovered.pcd"));
    // What is left is the broken one, still offered.
    QCOMPARE(window.checkUnfinishedJournals(), 1);
  }

  void anEmptyFolderOffersNothing() {
    QTemporaryDir folder;
    MainWindow window;
    window.hardwarePanel()->setScanFolder(folder.path());
    QCOMPARE(window.checkUnfinishedJournals(), 0);
    QVERIFY(!window.findChild<QAction*>("recoverAction")->isEnabled());
  }
};

QTEST_MAIN(JournalRecoveryTest)
#include "journal_recovery_test.moc"
