#include "clearway/hardware/serial_rosi.h"

#include <QFileInfo>
#include <QMetaObject>
#include <QPointer>

#include "clearway/hardware/acquisition_files.h"

namespace clearway::hardware {
namespace {

QString summaryOf(const PoseReading& pose) {
  const auto& t = pose.world_from_scanner.translation;
  QString text = pose.arm_tilt_deg ? SerialRosi::tr("arm tilt %1°, roll %2°")
                                         .arg(*pose.arm_tilt_deg, 0, 'f', 1)
                                         .arg(pose.arm_roll_deg.value_or(0.0), 0, 'f', 1)
                                   : SerialRosi::tr("fixed mounting");
  return text + SerialRosi::tr("; scanner at (%1, %2, %3) m")
                    .arg(t.x(), 0, 'f', 2)
                    .arg(t.y(), 0, 'f', 2)
                    .arg(t.z(), 0, 'f', 2);
}

}  // namespace

SerialRosi::SerialRosi(QString lms_port, QString turntable_port, int baud, QObject* parent)
    : ScannerDevice(parent),
      lms_port_(std::move(lms_port)),
      turntable_port_(std::move(turntable_port)),
      baud_(baud) {}

SerialRosi::~SerialRosi() {
  *cancel_ = true;
  join();
}

void SerialRosi::join() {
  if (worker_.joinable()) worker_.join();
}

QString SerialRosi::description() const {
  return tr("RoSi on %1 (laser, %2 baud) and %3 (turntable)")
      .arg(lms_port_, QString::number(baud_), turntable_port_);
}

void SerialRosi::doConnect() {
  // The devices are opened and configured for each scan; here only check that the ports exist.
  for (const QString& port : {lms_port_, turntable_port_}) {
    if (!QFileInfo::exists(port)) {
      fail(tr("There is no serial port %1. Is the scanner plugged in?").arg(port));
      return;
    }
  }
  // One port given for both would be "in use by another program" at the first scan.
  if (const std::string problem = checkDistinctPorts(
          {{"the laser port", "the laser scanner", lms_port_.toStdString()},
           {"the turntable port", "the turntable", turntable_port_.toStdString()}});
      !problem.empty()) {
    fail(QString::fromStdString(problem));
    return;
  }
  setState(State::kIdle);
}

void SerialRosi::doDisconnect() {
  *cancel_ = true;
  join();
}

void SerialRosi::doStartScan(const ScanRequest& request) {
  join();
  *cancel_ = false;
  AcquisitionOptions options;
  options.lines = request.lines;
  options.baud = baud_;
  options.journal = request.journal;
  if (request.turntable_speed_deg_s > 0)
    options.turntable_speed_deg_s = request.turntable_speed_deg_s;
  const int expected = request.lines > 0 ? request.lines : 300;
  QPointer<SerialRosi> self(this);
  auto cancel = cancel_;
  options.lines_arrived = [self](const Scan& so_far) {
    auto copy = std::make_shared<const Scan>(so_far);
    QMetaObject::invokeMethod(
        self,
        [self, copy] {
          if (self) emit self->linesArrived(copy);
        },
        Qt::QueuedConnection);
  };
  options.journal_failed = [self](const std::string& reason, std::size_t lines_journaled) {
    const QString text = tr("%1: the journal holds the first %2 lines. The scan goes on, its lines "
                            "kept in memory until it is saved.")
                             .arg(QString::fromStdString(reason), QString::number(lines_journaled));
    QMetaObject::invokeMethod(
        self,
        [self, text] {
          if (self) emit self->warning(text);
        },
        Qt::QueuedConnection);
  };
  last_pose_.reset();
  worker_ = std::thread([self, cancel, options, expected, pose_source = pose_source_,
                         lms = lms_port_.toStdString(),
                         table = turntable_port_.toStdString()]() mutable {
    if (pose_source) {
      // Where the scanner is, before it starts: a scan without its pose could put a wall on the
      // floor, so no pose, no scan.
      const PoseReading pose = pose_source->read(options.answer_timeout_ms);
      QMetaObject::invokeMethod(
          self,
          [self, pose] {
            if (!self) return;
            if (!pose.ok()) {
              if (self->state() == State::kScanning) self->setState(State::kIdle);
              emit self->failed(tr("No scan started: %1").arg(QString::fromStdString(pose.error)));
              return;
            }
            self->last_pose_ = pose;
            emit self->poseReceived(summaryOf(pose));
          },
          Qt::QueuedConnection);
      if (!pose.ok()) return;
      options.pose = pose;
    }
    const Acquisition acquisition = acquireRosiScan(lms, table, options, [&](double fraction) {
      QMetaObject::invokeMethod(
          self,
          [self, fraction, expected] {
            if (self) emit self->progress(int(fraction * expected), expected);
          },
          Qt::QueuedConnection);
      return !*cancel;
    });
    auto scan = std::make_shared<const Scan>(acquisition.scan);
    QMetaObject::invokeMethod(
        self,
        [self, scan, acquisition] {
          if (!self) return;
          // Disconnected meanwhile: the device stays disconnected.
          if (self->state() == State::kScanning) self->setState(State::kIdle);
          if (!acquisition.complete) emit self->failed(QString::fromStdString(acquisition.error));
          if (!scan->empty() || acquisition.complete)
            emit self->scanFinished(scan, acquisition.complete);
        },
        Qt::QueuedConnection);
  });
}

void SerialRosi::doCancel() {
  *cancel_ = true;
}

}  // namespace clearway::hardware
