#pragma once

// The scanner: choose the device (the simulated RoSi, or the RoSi on two serial ports with its
// arm and mounting), Connect, Disconnect, Scan (scan-and-stop), Cancel, live progress, the pose
// the arm reported, the ground-sample density the chosen line count gives, and the device's
// state in words. Each device shows only its own fields.
// Every acquisition is saved (atomically) before anything else happens, then handed on.

#include <QWidget>
#include <memory>

#include "clearway/scan.h"

namespace clearway::ui {

class HardwarePanel : public QWidget {
  Q_OBJECT

 public:
  explicit HardwarePanel(QWidget* parent = nullptr);
  ~HardwarePanel() override;

  // Where acquisitions are saved (default: the application data folder's "scans").
  void setScanFolder(const QString& folder);
  QString scanFolder() const;
  // True while an acquisition runs (its journal is being written).
  bool scanning() const;
  // Faster than real time, for demonstrations and tests.
  void setSpeedup(double speedup);
  // The robot's step, for the density readout (how far from the scanner ground can be green).
  void setRobotStep(double max_step);

 public slots:
  void connectScanner();
  void disconnectScanner();
  void startScan();
  void cancelScan();

 private slots:
  // Shows the ground-sample density the chosen line count gives (the "groundDensity" label).
  void showGroundDensity();

 signals:
  // A scan was acquired and saved; `complete` is false for the part kept after a cancel or loss.
  void scanSaved(const QString& path, bool complete);
  void statusChanged(const QString& status);
  // An acquisition started: what the views show is from now on the previous scan.
  void scanStarted();
  // An acquisition ended with nothing saved (cancelled before any line, or the save failed):
  // what the views show is the latest scan again.
  void scanEndedUnsaved();
  // The lines of the scan in progress, for the 3D view.
  void linesArrived(std::shared_ptr<const clearway::Scan> so_far);

 private:
  struct Private;
  std::unique_ptr<Private> d_;
};

}  // namespace clearway::ui
