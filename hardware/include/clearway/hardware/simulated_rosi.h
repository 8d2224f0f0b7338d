#pragma once

// The RoSi simulated in-process: a ScannerDevice that observes one of the simulator's scenes and
// delivers its lines at the LMS200's line rate (scaled by `speedup`, so tests stay quick).

#include <QTimer>
#include <memory>
#include <string>

#include "clearway/hardware/scanner_device.h"
#include "clearway/sim/scene.h"

namespace clearway::hardware {

class SimulatedRosi : public ScannerDevice {
  Q_OBJECT

 public:
  explicit SimulatedRosi(sim::Scene scene, QObject* parent = nullptr);
  ~SimulatedRosi() override;

  QString description() const override;
  // 1 = real time (37.5 lines/s); larger is faster.
  void setSpeedup(double speedup) { speedup_ = speedup; }

 protected:
  void doConnect() override;
  void doDisconnect() override;
  void doStartScan(const ScanRequest& request) override;
  void doCancel() override;

 private:
  void deliverLines();

  sim::Scene scene_;
  double speedup_ = 1.0;
  QTimer line_timer_;
  std::shared_ptr<Scan> full_scan_;  // the whole revolution, delivered line by line
  int delivered_ = 0;
};

}  // namespace clearway::hardware
