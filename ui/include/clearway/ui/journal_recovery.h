#pragma once

// The console's side of "nothing the operator acquired is lost": journals left in the scans
// folder by acquisitions that did not finish (the console crashed, the power went, the disk
// refused the scan) are found and turned into scans off the GUI thread (hardware's
// journal_recovery, the same as `clearway-cli acquire --recover`).

#include <QFutureWatcher>
#include <QObject>
#include <QStringList>

namespace clearway::ui {

class JournalRecovery : public QObject {
  Q_OBJECT

 public:
  explicit JournalRecovery(QObject* parent = nullptr);

  // The journals left in `folder`, oldest first.
  static QStringList unfinished(const QString& folder);
  // Recovers each journal into SCAN-recovered.pcd beside it, in the background; `finished`
  // follows. Ignored while a recovery runs.
  void recover(const QStringList& journals);
  bool busy() const { return watcher_.isRunning(); }

 signals:
  // The scans written (in the order given) and, for each journal that could not be recovered,
  // the reason naming it (the journal is then kept).
  void finished(const QStringList& scans, const QStringList& problems);

 private:
  struct Outcome {
    QStringList scans;
    QStringList problems;
  };
  QFutureWatcher<Outcome> watcher_;
};

}  // namespace clearway::ui
