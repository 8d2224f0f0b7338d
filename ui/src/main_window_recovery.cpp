// The main window's recovery of interrupted acquisitions: journals left in the scans folder by a
// crash, a power cut or a scan the disk refused become scans again (docs/JOURNAL.md).

#include <QAction>
#include <QStatusBar>

#include "clearway/ui/hardware_panel.h"
#include "clearway/ui/journal_recovery.h"
#include "main_window_private.h"

namespace clearway::ui {

void MainWindow::setUpJournalRecovery() {
  d_->recovery = new JournalRecovery(this);
  connect(d_->recovery, &JournalRecovery::finished, this,
          [this](const QStringList& scans, const QStringList& problems) {
            QString message;
            if (!scans.isEmpty())
              message = tr("Recovered %n interrupted acquisition(s): %1.", "", int(scans.size()))
                            .arg(scans.join(", "));
            if (!problems.isEmpty())
              message +=
                  (message.isEmpty() ? "" : " ") + tr("Not recovered: %1").arg(problems.join("; "));
            statusBar()->showMessage(message);
            updateRecoverAction();
            if (!scans.isEmpty()) openScan(scans.back());
            emit journalsRecovered(scans, problems);
          });
  // A scan that could not be saved leaves its journal: offered as soon as the device is idle,
  // in the File menu only (the status bar keeps what the operator is reading).
  connect(d_->hardware, &HardwarePanel::statusChanged, this, [this] { updateRecoverAction(); });
}

int MainWindow::updateRecoverAction() {
  // The journal of a scan in progress is being written: never touch it.
  const int count = d_->hardware->scanning()
                        ? 0
                        : int(JournalRecovery::unfinished(d_->hardware->scanFolder()).size());
  d_->recover_action->setEnabled(count > 0 && !d_->recovery->busy());
  d_->recover_action->setText(count > 0 ? tr("&Recover interrupted acquisitions (%1)").arg(count)
                                        : tr("&Recover interrupted acquisitions"));
  return count;
}

int MainWindow::checkUnfinishedJournals() {
  const int count = updateRecoverAction();
  if (count > 0 && !d_->recovery->busy())
    statusBar()->showMessage(tr("%n interrupted acquisition(s) in %1 can be recovered: File > "
                                "Recover interrupted acquisitions.",
                                "", count)
                                 .arg(d_->hardware->scanFolder()));
  return count;
}

void MainWindow::recoverInterruptedAcquisitions() {
  if (updateRecoverAction() == 0 || d_->recovery->busy()) return;
  d_->recover_action->setEnabled(false);
  statusBar()->showMessage(tr("Recovering interrupted acquisitions ..."));
  d_->recovery->recover(JournalRecovery::unfinished(d_->hardware->scanFolder()));
}

}  // namespace clearway::ui
