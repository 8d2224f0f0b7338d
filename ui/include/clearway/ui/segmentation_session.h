#pragma once

// The console's engine room: loads a scan and runs the pipeline in the background, keeps the scan
// analysis, and re-runs only the traversability check when the robot changes — debounced, newest
// request wins, never blocking the GUI thread (Qt5: QtConcurrent + QFutureWatcher).

#include <QDateTime>
#include <QObject>
#include <QString>
#include <memory>

#include "clearway/pipeline.h"
#include "clearway/pose.h"
#include "clearway/scan.h"
#include "clearway/segmentation/params.h"

namespace clearway::ui {

// What the window shows: the scan and the result of the pipeline on it.
struct SessionResult {
  std::shared_ptr<const Scan> scan;
  std::shared_ptr<const PipelineResult> result;
  QString scan_path;
  // When the scan was taken: the time acquisition recorded in its pose sidecar when there is one
  // (scan_time_recorded), else when the file was last saved (a copy's time, for a copied file).
  QDateTime scan_time;
  bool scan_time_recorded = false;
  // Where the scan's pose came from (core's resolution: console > sidecar > file).
  PoseResolution pose;
  // The scan was saved from an acquisition that ended early (cancelled, a device lost, a crash
  // recovered from its journal): part of the turn is missing. The acquisition's record beside the
  // scan decides (SCAN.acquisition.json's "complete"; `partial_reason`, its "reason", may be
  // empty); without one, the name Clearway gives such a scan (SCAN.partial.pcd from `acquire`,
  // ...-partial.pcd from the Scanner panel and `serve`).
  bool partial = false;
  QString partial_reason;
};

class SegmentationSession : public QObject {
  Q_OBJECT

 public:
  explicit SegmentationSession(QObject* parent = nullptr);
  ~SegmentationSession() override;  // waits for running work, which it cancels first

  // Loads and segments a scan file; cancels any job still running.
  void openScan(const QString& path);
  // Segments the scan already loaded again with the current parameters (stages 1-6, no reload).
  void resegment();
  // Gives the loaded scan the operator's pose (typed: kCommandLine; a confirmed estimate or a
  // picked floor: kOperator) through core's resolveScanPose, and segments it again. The pose
  // belongs to this scan: the next scan opened is resolved from its own sources.
  void setScanPose(const PoseRequest& request, PoseSource source);
  // True while a scan and its result are held (a failed or cancelled open drops them).
  bool hasResult() const;
  // Re-runs stages 5-6 for a new robot after a short pause (slider drags coalesce).
  void setRobot(const RobotParams& robot);
  void setParams(const SegmentationParams& params);
  const SegmentationParams& params() const { return params_; }
  // Threads every later job uses (load, re-segment, robot re-run), clamped
  // to 1..clearway::kMaxThreads; the running job keeps its own.
  void setThreads(int threads);
  int threads() const { return threads_; }
  void cancel();
  bool busy() const;

  // Milliseconds a robot change waits for the next one before the re-run starts.
  static constexpr int kRobotDebounceMs = 120;

 signals:
  void progress(int percent, const QString& what);
  void resultReady(const clearway::ui::SessionResult& result);
  void failed(const QString& reason);
  // The scan file `path` could not be opened (a load, not a re-run): follows its `failed`.
  void openFailed(const QString& path, const QString& reason);
  // The operator cancelled the work: not a failure to report.
  void cancelled();
  void busyChanged(bool busy);

 private:
  struct Private;
  std::unique_ptr<Private> d_;
  SegmentationParams params_;
  int threads_ = kDefaultThreads;
};

}  // namespace clearway::ui

Q_DECLARE_METATYPE(clearway::ui::SessionResult)
