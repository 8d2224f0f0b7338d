#pragma once

// The scan's pose for the operator: where it came from in words, and a small dialog to type or
// correct it (a full pose tx,ty,tz,qw,qx,qy,qz as in PCD VIEWPOINT, or only the up direction
// X,Y,Z in the scanner frame), validated by core's own parsers before OK is enabled.

#include <QDialog>
#include <QString>

#include "clearway/pose.h"

class QComboBox;
class QLabel;
class QLineEdit;
class QPushButton;

namespace clearway::ui {

// "from the file (PCD VIEWPOINT)", "estimated from the scan (confidence 0.82)", ...
QString poseSourceInWords(PoseSource source, double up_confidence = 1.0);

// The request `text` asks for: a pose (7 numbers) when `whole_pose`, else an up direction (3).
// Empty `error` on success; otherwise core's reason.
PoseRequest poseRequestFromText(bool whole_pose, const QString& text, QString* error);

class PoseDialog : public QDialog {
  Q_OBJECT

 public:
  explicit PoseDialog(QWidget* parent = nullptr);

  // What the operator typed, valid once the dialog is accepted.
  PoseRequest request() const { return request_; }

 private:
  void validate();

  QComboBox* kind_ = nullptr;
  QLineEdit* text_ = nullptr;
  QLabel* problem_ = nullptr;
  QPushButton* ok_ = nullptr;
  PoseRequest request_;
};

}  // namespace clearway::ui
