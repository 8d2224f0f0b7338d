#include "clearway/hardware/scanner_device.h"

namespace clearway::hardware {

ScannerDevice::ScannerDevice(QObject* parent) : QObject(parent) {}
ScannerDevice::~ScannerDevice() = default;

void ScannerDevice::connectDevice() {
  if (state_ != State::kDisconnected && state_ != State::kFailed) return;
  setState(State::kConnecting);
  doConnect();
}

void ScannerDevice::disconnectDevice() {
  if (state_ == State::kDisconnected) return;
  if (state_ == State::kScanning) doCancel();
  doDisconnect();
  setState(State::kDisconnected);
}

void ScannerDevice::startScan(const ScanRequest& request) {
  if (state_ != State::kIdle) {
    emit failed(tr("The scanner is not ready (%1).").arg(stateName(state_)));
    return;
  }
  setState(State::kScanning);
  doStartScan(request);
}

void ScannerDevice::cancelScan() {
  if (state_ == State::kScanning) doCancel();
}

QString ScannerDevice::stateName(State state) {
  switch (state) {
    case State::kDisconnected:
      return tr("disconnected");
    case State::kConnecting:
      return tr("connecting");
    case State::kIdle:
      return tr("ready");
    case State::kScanning:
      return tr("scanning");
    case State::kFailed:
      return tr("failed");
  }
  return {};
}

void ScannerDevice::setState(State state) {
  if (state_ == state) return;
  state_ = state;
  emit stateChanged(state);
}

void ScannerDevice::fail(const QString& reason) {
  setState(State::kFailed);
  emit failed(reason);
}

}  // namespace clearway::hardware
