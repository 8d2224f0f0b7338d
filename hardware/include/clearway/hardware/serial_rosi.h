#pragma once

// The real RoSi behind ScannerDevice: an LMS200 and a turntable on two serial ports. A scan runs
// acquireRosiScan on a thread of its own; progress and the result come back on the object's thread.

#include <QString>
#include <atomic>
#include <memory>
#include <optional>
#include <thread>

#include "clearway/hardware/pose_source.h"
#include "clearway/hardware/scanner_device.h"
#include "clearway/hardware/serial_acquisition.h"

namespace clearway::hardware {

class SerialRosi : public ScannerDevice {
  Q_OBJECT

 public:
  // `baud`: the link speed the LMS200 is switched to after setup (9600, 19200, 38400, 500000).
  SerialRosi(QString lms_port, QString turntable_port, int baud = AcquisitionOptions{}.baud,
             QObject* parent = nullptr);
  ~SerialRosi() override;  // cancels and waits for a running scan

  QString description() const override;
  // Asked for the scanner's pose before every scan (the arm, or a fixed mounting); the scan
  // carries it as its sensor pose. None: the scan has no pose.
  void setPoseSource(std::shared_ptr<PoseSource> source) { pose_source_ = std::move(source); }
  // The pose of the last scan started, for its SCAN.pose.json.
  const std::optional<PoseReading>& lastPose() const { return last_pose_; }

 protected:
  void doConnect() override;
  void doDisconnect() override;
  void doStartScan(const ScanRequest& request) override;
  void doCancel() override;

 private:
  void join();
  QString lms_port_, turntable_port_;
  int baud_;
  std::shared_ptr<PoseSource> pose_source_;
  std::optional<PoseReading> last_pose_;
  std::thread worker_;
  std::shared_ptr<std::atomic<bool>> cancel_ = std::make_shared<std::atomic<bool>>(false);
};

}  // namespace clearway::hardware
