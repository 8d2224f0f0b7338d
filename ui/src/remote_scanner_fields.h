#pragma once

// The Scanner panel's fields for the remote RoSi (`clearway-cli serve` on the robot): host, port,
// credentials folder, and the link's state in words. Kept apart from the panel so the panel only
// adds a device choice and a row.

#include <QWidget>
#include <memory>

class QLabel;
class QLineEdit;
class QSpinBox;

namespace clearway::hardware {
class ScannerDevice;
}

namespace clearway::ui {

class RemoteScannerFields : public QWidget {
  Q_OBJECT

 public:
  explicit RemoteScannerFields(QWidget* parent = nullptr);

  // A remote RoSi for the fields' host, port and credentials, with its link state shown in the
  // fields; nullptr and a readable `problem` (naming the credentials file) when they are unusable.
  std::unique_ptr<hardware::ScannerDevice> createDevice(QString* problem);

 private:
  QLineEdit* host_ = nullptr;
  QSpinBox* port_ = nullptr;
  QLineEdit* credentials_ = nullptr;
  QLabel* link_ = nullptr;
};

}  // namespace clearway::ui
