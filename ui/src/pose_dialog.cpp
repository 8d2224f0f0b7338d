#include "clearway/ui/pose_dialog.h"

#include <QComboBox>
#include <QDialogButtonBox>
#include <QFormLayout>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <stdexcept>

namespace clearway::ui {
namespace {

// The choices of the kind combo box, in order.
enum KindIndex { kUpIndex = 0, kPoseIndex = 1 };

}  // namespace

QString poseSourceInWords(PoseSource source, double up_confidence) {
  switch (source) {
    case PoseSource::kNone:
      return QObject::tr("none: the scan has no pose");
    case PoseSource::kFile:
      return QObject::tr("from the scan file");
    case PoseSource::kSidecar:
      return QObject::tr("from the acquisition's pose file (sidecar)");
    case PoseSource::kCommandLine:
      return QObject::tr("typed by the operator");
    case PoseSource::kOperator:
      return QObject::tr("confirmed by the operator");
    case PoseSource::kEstimated:
      return QObject::tr("estimated from the scan (confidence %1)").arg(up_confidence, 0, 'f', 2);
  }
  return {};
}

PoseRequest poseRequestFromText(bool whole_pose, const QString& text, QString* error) {
  PoseRequest request;
  error->clear();
  try {
    if (whole_pose)
      request.pose = parsePoseText(text.trimmed().toStdString());
    else
      request.up = parseUpText(text.trimmed().toStdString());
  } catch (const std::invalid_argument& problem) {
    *error = QString::fromUtf8(problem.what());
  }
  return request;
}

PoseDialog::PoseDialog(QWidget* parent) : QDialog(parent) {
  setObjectName("poseDialog");
  setWindowTitle(tr("The scan's pose"));
  auto* layout = new QFormLayout(this);
  kind_ = new QComboBox(this);
  kind_->setObjectName("poseKind");
  kind_->insertItem(kUpIndex, tr("Up direction X,Y,Z (scanner frame)"));
  kind_->insertItem(kPoseIndex, tr("Pose tx,ty,tz,qw,qx,qy,qz (world from scanner)"));
  text_ = new QLineEdit(this);
  text_->setObjectName("poseText");
  text_->setPlaceholderText("0,0,1");
  problem_ = new QLabel(this);
  problem_->setObjectName("poseProblem");
  problem_->setWordWrap(true);
  problem_->setStyleSheet("QLabel { color: #c62828; }");
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel, this);
  ok_ = buttons->button(QDialogButtonBox::Ok);
  ok_->setObjectName("poseOk");
  ok_->setText(tr("Segment with this pose"));
  layout->addRow(tr("Give:"), kind_);
  layout->addRow(tr("Values:"), text_);
  layout->addRow(problem_);
  layout->addRow(buttons);
  connect(kind_, qOverload<int>(&QComboBox::currentIndexChanged), this, [this](int index) {
    text_->setPlaceholderText(index == kPoseIndex ? "0,0,0.5,1,0,0,0" : "0,0,1");
    validate();
  });
  connect(text_, &QLineEdit::textChanged, this, &PoseDialog::validate);
  connect(buttons, &QDialogButtonBox::accepted, this, &QDialog::accept);
  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
  validate();
}

void PoseDialog::validate() {
  QString error;
  request_ = poseRequestFromText(kind_->currentIndex() == kPoseIndex, text_->text(), &error);
  if (text_->text().trimmed().isEmpty()) error = tr("Type the values, separated by commas.");
  problem_->setText(error);
  ok_->setEnabled(error.isEmpty());
}

}  // namespace clearway::ui
