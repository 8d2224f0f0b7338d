#pragma once

// The RoSi as the console sees it: connect, scan (scan-and-stop), cancel, lines as they arrive.
// Public calls are non-virtual and keep the state machine honest; implementations (simulated,
// serial) override the protected do*() hooks. The GUI never knows which implementation it has.

#include <QObject>
#include <QString>
#include <memory>
#include <string>

#include "clearway/scan.h"

namespace clearway::hardware {

struct ScanRequest {
  int lines = 0;                       // 0 = one full revolution at the configured speed
  double turntable_speed_deg_s = 0.0;  // 0 = the device's default
  // Real devices: every line is journaled here as it arrives (docs/JOURNAL.md), so a crash of the
  // console loses none; the caller removes it once the scan is saved. Empty: no journal.
  std::string journal;
};

class ScannerDevice : public QObject {
  Q_OBJECT

 public:
  enum class State { kDisconnected, kConnecting, kIdle, kScanning, kFailed };
  Q_ENUM(State)

  explicit ScannerDevice(QObject* parent = nullptr);
  ~ScannerDevice() override;

  void connectDevice();
  void disconnectDevice();
  // Starts a scan; ignored (with failed()) unless the device is idle.
  void startScan(const ScanRequest& request);
  void cancelScan();

  State state() const { return state_; }
  virtual QString description() const = 0;
  static QString stateName(State state);

 signals:
  void stateChanged(clearway::hardware::ScannerDevice::State state);
  // A line arrived: `received` of `expected` lines so far.
  void progress(int received, int expected);
  // The lines so far, as a scan (throttled): the console shows the cloud growing.
  void linesArrived(std::shared_ptr<const clearway::Scan> so_far);
  // The scan is complete (or, with `complete` false, the part that arrived before a failure).
  void scanFinished(std::shared_ptr<const clearway::Scan> scan, bool complete);
  // An operator-readable reason.
  void failed(const QString& reason);
  // Something the operator must know at once that does not end the scan (its journal's disk is
  // full: the lines go on into memory, and only those before are safe from a crash).
  void warning(const QString& text);
  // Where the scanner is for the scan that starts (e.g. the arm's tilt and roll), in words.
  void poseReceived(const QString& summary);

 protected:
  virtual void doConnect() = 0;
  virtual void doDisconnect() = 0;
  virtual void doStartScan(const ScanRequest& request) = 0;
  virtual void doCancel() = 0;
  void setState(State state);
  void fail(const QString& reason);

 private:
  State state_ = State::kDisconnected;
};

}  // namespace clearway::hardware
