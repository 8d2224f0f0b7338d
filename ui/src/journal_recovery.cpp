#include "clearway/ui/journal_recovery.h"

#include <QtConcurrent/QtConcurrentRun>
#include <exception>

#include "clearway/hardware/journal_recovery.h"

namespace clearway::ui {

JournalRecovery::JournalRecovery(QObject* parent) : QObject(parent) {
  connect(&watcher_, &QFutureWatcher<Outcome>::finished, this, [this] {
    const Outcome outcome = watcher_.result();
    emit finished(outcome.scans, outcome.problems);
  });
}

QStringList JournalRecovery::unfinished(const QString& folder) {
  QStringList journals;
  for (const auto& journal : hardware::unfinishedJournals(folder.toStdString()))
    journals << QString::fromStdString(journal.string());
  return journals;
}

void JournalRecovery::recover(const QStringList& journals) {
  if (busy()) return;
  watcher_.setFuture(QtConcurrent::run([journals] {
    Outcome outcome;
    for (const QString& journal : journals) {
      const std::filesystem::path path = journal.toStdString();
      const std::filesystem::path scan = hardware::recoveredScanPathFor(path);
      try {
        hardware::recoverJournalInto(path, scan);
        outcome.scans << QString::fromStdString(scan.string());
      } catch (const std::exception& error) {
        // ScanError names the file; anything else (a full disk) is said as it is.
        outcome.problems << QString::fromUtf8(error.what());
      }
    }
    return outcome;
  }));
}

}  // namespace clearway::ui
