#include "clearway/ui/segmentation_session.h"

#include <QFile>
#include <QFileInfo>
#include <QFutureWatcher>
#include <QJsonDocument>
#include <QJsonObject>
#include <QJsonValue>
#include <QPointer>
#include <QTimer>
#include <QtConcurrent/QtConcurrentRun>
#include <algorithm>
#include <atomic>

#include "clearway/hardware/acquisition_files.h"
#include "clearway/io/scan_io.h"
#include "clearway/pose.h"

namespace clearway::ui {
namespace {

// The time acquisition wrote into the scan's pose sidecar ("time", ISO 8601 UTC), when there is
// one: a copied or re-saved file's modification time is not when the scan was taken.
QDateTime recordedScanTime(const QString& scan_path) {
  const auto sidecar = findPoseSidecar(scan_path.toStdString());
  if (!sidecar) return {};
  QFile file(QString::fromStdString(sidecar->string()));
  if (!file.open(QIODevice::ReadOnly)) return {};
  const QJsonValue time = QJsonDocument::fromJson(file.readAll()).object().value("time");
  QDateTime parsed = QDateTime::fromString(time.toString(), Qt::ISODate);
  return parsed.isValid() ? parsed.toLocalTime() : QDateTime();
}

// Fills `result.partial` for the scan at `scan_path` (see SessionResult).
void readCompleteness(const QString& scan_path, SessionResult& result) {
  const hardware::ScanCompleteness completeness =
      hardware::scanCompleteness(scan_path.toStdString());
  result.partial = completeness.partial;
  result.partial_reason = QString::fromStdString(completeness.reason).trimmed();
}

struct JobOutcome {
  SessionResult result;
  QString error;  // empty on success
  bool cancelled = false;
  bool opened_file = false;  // the job loaded result.scan_path (not a re-run on a loaded scan)
};

// Shared between the GUI thread and one job: the job reads it through the progress callback.
struct JobControl {
  std::atomic<bool> cancel{false};
  std::atomic<int> percent{0};
};

JobOutcome loadAndSegment(const QString& path, const SegmentationParams& params, int threads,
                          std::shared_ptr<JobControl> control) {
  JobOutcome outcome;
  outcome.result.scan_path = path;
  outcome.opened_file = true;
  try {
    LoadOptions options;
    options.progress = [control](double f) {
      control->percent = int(30 * f);
      return !control->cancel;
    };
    options.self_hit_radius = params.scan.self_hit_radius;
    Scan loaded = loadScan(path.toStdString(), options);
    // The same precedence as the command line: a sidecar beside the scan, then the file's own.
    outcome.result.pose = resolveScanPose(loaded, {});
    auto scan = std::make_shared<const Scan>(std::move(loaded));
    auto result = std::make_shared<const PipelineResult>(
        runPipeline(*scan, params, threads, [control](double f) {
          control->percent = 30 + int(70 * f);
          return !control->cancel;
        }));
    outcome.result.scan = std::move(scan);
    outcome.result.scan_time = QFileInfo(path).lastModified();
    if (const QDateTime recorded = recordedScanTime(path); recorded.isValid()) {
      outcome.result.scan_time = recorded;
      outcome.result.scan_time_recorded = true;
    }
    readCompleteness(path, outcome.result);
    outcome.result.result = std::move(result);
  } catch (const OperationCancelled&) {
    outcome.cancelled = true;
  } catch (const std::exception& error) {
    outcome.error = QString::fromUtf8(error.what());
  }
  return outcome;
}

JobOutcome resegmentScan(SessionResult previous, const SegmentationParams& params, int threads,
                         std::shared_ptr<JobControl> control) {
  JobOutcome outcome;
  outcome.result = previous;
  try {
    outcome.result.result = std::make_shared<const PipelineResult>(
        runPipeline(*previous.scan, params, threads, [control](double f) {
          control->percent = int(100 * f);
          return !control->cancel;
        }));
  } catch (const OperationCancelled&) {
    outcome.cancelled = true;
  } catch (const std::exception& error) {
    outcome.error = QString::fromUtf8(error.what());
  }
  return outcome;
}

JobOutcome rerun(SessionResult previous, const SegmentationParams& params, int threads,
                 std::shared_ptr<JobControl> control) {
  JobOutcome outcome;
  outcome.result = previous;
  try {
    outcome.result.result = std::make_shared<const PipelineResult>(rerunForRobot(
        *previous.scan, previous.result->analysis, params, threads, [control](double f) {
          control->percent = int(100 * f);
          return !control->cancel;
        }));
  } catch (const OperationCancelled&) {
    outcome.cancelled = true;
  } catch (const std::exception& error) {
    outcome.error = QString::fromUtf8(error.what());
  }
  return outcome;
}

}  // namespace

struct SegmentationSession::Private {
  QFutureWatcher<JobOutcome> load_watcher;
  QFutureWatcher<JobOutcome> robot_watcher;
  std::shared_ptr<JobControl> control;
  QTimer robot_timer;
  QTimer progress_timer;
  SessionResult current;
  bool robot_pending = false;
  QString progress_label;  // what the progress bar names while progress_timer runs
};

SegmentationSession::SegmentationSession(QObject* parent)
    : QObject(parent), d_(std::make_unique<Private>()) {
  qRegisterMetaType<SessionResult>();
  d_->robot_timer.setSingleShot(true);
  d_->robot_timer.setInterval(kRobotDebounceMs);
  d_->progress_timer.setInterval(50);

  connect(&d_->progress_timer, &QTimer::timeout, this, [this] {
    if (d_->control) emit progress(d_->control->percent, d_->progress_label);
  });
  connect(&d_->load_watcher, &QFutureWatcher<JobOutcome>::finished, this, [this] {
    d_->progress_timer.stop();
    const JobOutcome outcome = d_->load_watcher.result();
    emit busyChanged(busy());
    if (outcome.cancelled) {
      emit cancelled();
    } else if (!outcome.error.isEmpty()) {
      emit failed(outcome.error);
      if (outcome.opened_file) emit openFailed(outcome.result.scan_path, outcome.error);
    } else {
      d_->current = outcome.result;
      emit progress(100, tr("Done"));
      emit resultReady(d_->current);
      if (d_->robot_pending) d_->robot_timer.start();
    }
  });
  connect(&d_->robot_timer, &QTimer::timeout, this, [this] {
    if (!d_->current.result || d_->load_watcher.isRunning()) return;
    if (d_->robot_watcher.isRunning()) {  // the newest request runs when this one ends
      d_->robot_pending = true;
      return;
    }
    d_->robot_pending = false;
    // Reported and cancelled as a load is: a 10M-point scan's re-run takes seconds, and the bar
    // said "Done 100 %" beside a Cancel that did nothing meanwhile.
    d_->control = std::make_shared<JobControl>();
    emit busyChanged(true);
    d_->progress_label = tr("New robot");
    emit progress(0, d_->progress_label);
    d_->progress_timer.start();
    d_->robot_watcher.setFuture(
        QtConcurrent::run(rerun, d_->current, params_, threads_, d_->control));
  });
  connect(&d_->robot_watcher, &QFutureWatcher<JobOutcome>::finished, this, [this] {
    const JobOutcome outcome = d_->robot_watcher.result();
    if (!d_->load_watcher.isRunning()) d_->progress_timer.stop();
    emit busyChanged(busy());
    if (outcome.cancelled) {
      // The shown map stays the previous robot's, as its title says; no error to report.
      if (outcome.result.scan == d_->current.scan) emit cancelled();
    } else if (!outcome.error.isEmpty()) {
      emit failed(outcome.error);
    } else if (outcome.result.scan == d_->current.scan) {  // not a result for a scan since replaced
      d_->current = outcome.result;
      emit resultReady(d_->current);
    }
    if (d_->robot_pending) d_->robot_timer.start(0);
  });
}

SegmentationSession::~SegmentationSession() {
  cancel();
  d_->load_watcher.waitForFinished();
  d_->robot_watcher.waitForFinished();
}

void SegmentationSession::openScan(const QString& path) {
  // A job still running is told to stop and forgotten: the watcher follows the new one, so the
  // GUI thread never waits for it.
  cancel();
  d_->control = std::make_shared<JobControl>();
  d_->current = {};
  emit busyChanged(true);
  d_->progress_label = tr("Segmenting");
  emit progress(0, tr("Loading"));
  d_->progress_timer.start();
  d_->load_watcher.setFuture(
      QtConcurrent::run(loadAndSegment, path, params_, threads_, d_->control));
}

void SegmentationSession::resegment() {
  if (!d_->current.scan) return;
  const SessionResult previous = d_->current;
  cancel();
  d_->control = std::make_shared<JobControl>();
  d_->current = {};
  emit busyChanged(true);
  d_->progress_label = tr("Segmenting");
  emit progress(0, d_->progress_label);
  d_->progress_timer.start();
  d_->load_watcher.setFuture(
      QtConcurrent::run(resegmentScan, previous, params_, threads_, d_->control));
}

void SegmentationSession::setScanPose(const PoseRequest& request, PoseSource source) {
  if (!d_->current.scan) return;
  auto posed = std::make_shared<Scan>(*d_->current.scan);
  d_->current.pose = resolveScanPose(*posed, request);
  posed->pose_source = source;
  d_->current.pose.source = source;
  d_->current.scan = std::move(posed);
  resegment();
}

bool SegmentationSession::hasResult() const {
  return d_->current.result != nullptr;
}

void SegmentationSession::setRobot(const RobotParams& robot) {
  params_.robot = robot;
  d_->robot_pending = true;
  d_->robot_timer.start();
}

void SegmentationSession::setParams(const SegmentationParams& params) {
  params_ = params;
  d_->robot_pending = true;
  d_->robot_timer.start();
}

void SegmentationSession::setThreads(int threads) {
  threads_ = std::clamp(threads, 1, kMaxThreads);
}

void SegmentationSession::cancel() {
  if (d_->control) d_->control->cancel = true;
}

bool SegmentationSession::busy() const {
  return d_->load_watcher.isRunning() || d_->robot_watcher.isRunning();
}

}  // namespace clearway::ui
