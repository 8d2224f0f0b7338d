#include "clearway/ui/parameters_dialog.h"

#include <QComboBox>
#include <QDialogButtonBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGroupBox>
#include <QGuiApplication>
#include <QLabel>
#include <QPushButton>
#include <QScreen>
#include <QScrollArea>
#include <QVBoxLayout>
#include <algorithm>
#include <map>

namespace clearway::ui {
namespace {

// The dialog's size, and the most of the screen's free area it takes.
const QSize kDefaultSize(560, 640);
constexpr double kScreenShare = 0.92;

QString stageTitle(const std::string& stage) {
  if (stage == "lines") return QObject::tr("1  Line segments (per scan line)");
  if (stage == "clustering") return QObject::tr("2  Planes from segments");
  if (stage == "validation") return QObject::tr("3  Plane validation (support)");
  if (stage == "ground") return QObject::tr("4  Ground");
  if (stage == "map") return QObject::tr("5  Traversability map");
  if (stage == "robot") return QObject::tr("Robot");
  return QString::fromStdString(stage);
}

}  // namespace

struct ParametersDialog::Private {
  SegmentationParams params;
  std::map<std::string, QDoubleSpinBox*> fields;
  QComboBox* method = nullptr;
  QLabel* problems = nullptr;
  QDialogButtonBox* buttons = nullptr;
};

ParametersDialog::ParametersDialog(const SegmentationParams& params, QWidget* parent)
    : QDialog(parent), d_(std::make_unique<Private>()) {
  setObjectName("parametersDialog");
  setWindowTitle(tr("Segmentation parameters"));
  d_->params = params;
  // One group per pipeline stage, each field named in words with its unit; the key stays in the
  // tool tip for those who edit JSON.
  auto* form_widget = new QWidget(this);
  auto* groups = new QVBoxLayout(form_widget);
  std::map<std::string, QFormLayout*> forms;
  auto formFor = [&](const std::string& key) {
    const std::string stage = key.substr(0, key.find('.'));
    if (auto it = forms.find(stage); it != forms.end()) return it->second;
    auto* box = new QGroupBox(stageTitle(stage), form_widget);
    box->setObjectName(QString::fromStdString("group_" + stage));
    auto* form = new QFormLayout(box);
    groups->addWidget(box);
    forms[stage] = form;
    return form;
  };
  d_->method = new QComboBox(form_widget);
  d_->method->setObjectName("lines_method");
  d_->method->addItems({tr("split and merge"), tr("Hough (the paper's)")});
  d_->method->setCurrentIndex(params.lines.method == LineMethod::kHough ? 1 : 0);
  d_->method->setToolTip("lines.method");
  formFor("lines.method")->addRow(tr("Line detection method"), d_->method);
  for (const ParameterInfo& info : describeParameters()) {
    auto* spin = new QDoubleSpinBox(form_widget);
    spin->setObjectName(QString::fromStdString(info.key).replace('.', '_'));
    spin->setRange(info.minimum, info.maximum);
    spin->setDecimals(info.integer ? 0 : 3);
    spin->setSingleStep(info.integer ? 1.0 : (info.maximum - info.minimum) / 200.0);
    spin->setValue(parameterValue(params, info.key));
    spin->setToolTip(
        tr("%1 (default %2)").arg(QString::fromStdString(info.key)).arg(info.default_value));
    auto* label = new QLabel(QString::fromStdString(info.description), form_widget);
    label->setObjectName(spin->objectName() + "_label");
    formFor(info.key)->addRow(label, spin);
    d_->fields[info.key] = spin;
    connect(spin, qOverload<double>(&QDoubleSpinBox::valueChanged), this,
            &ParametersDialog::refresh);
  }
  groups->addStretch(1);
  auto* scroll = new QScrollArea(this);
  scroll->setWidget(form_widget);
  scroll->setWidgetResizable(true);
  d_->problems = new QLabel(this);
  d_->problems->setObjectName("parameterProblems");
  d_->problems->setStyleSheet("QLabel { color: #b71c1c; }");
  d_->problems->setWordWrap(true);
  d_->buttons = new QDialogButtonBox(
      QDialogButtonBox::Ok | QDialogButtonBox::Cancel | QDialogButtonBox::RestoreDefaults, this);
  connect(d_->buttons, &QDialogButtonBox::accepted, this, &QDialog::accept);
  connect(d_->buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
  connect(d_->buttons->button(QDialogButtonBox::RestoreDefaults), &QPushButton::clicked, this,
          [this] {
            const SegmentationParams defaults;
            for (auto& [key, spin] : d_->fields)
              spin->setValue(parameterValue(defaults, key));
            d_->method->setCurrentIndex(0);
          });
  auto* layout = new QVBoxLayout(this);
  layout->addWidget(scroll, 1);
  layout->addWidget(d_->problems);
  layout->addWidget(d_->buttons);
  // Fits the screen it opens on: on a 1024 x 600 field laptop OK and Cancel were below its edge
  // (the groups scroll).
  const QScreen* screen = parent ? parent->screen() : QGuiApplication::primaryScreen();
  const QSize available = screen ? screen->availableGeometry().size() : kDefaultSize;
  resize(std::min(kDefaultSize.width(), int(available.width() * kScreenShare)),
         std::min(kDefaultSize.height(), int(available.height() * kScreenShare)));
  refresh();
}

ParametersDialog::~ParametersDialog() = default;

SegmentationParams ParametersDialog::params() const {
  SegmentationParams params = d_->params;
  for (const auto& [key, spin] : d_->fields)
    setParameterValue(params, key, spin->value());
  params.lines.method =
      d_->method->currentIndex() == 1 ? LineMethod::kHough : LineMethod::kSplitAndMerge;
  return params;
}

QStringList ParametersDialog::problems() const {
  QStringList list;
  for (const std::string& reason : params().validate())
    list << QString::fromStdString(reason);
  return list;
}

void ParametersDialog::refresh() {
  const QStringList list = problems();
  d_->problems->setText(list.join("\n"));
  d_->problems->setVisible(!list.isEmpty());
  d_->buttons->button(QDialogButtonBox::Ok)->setEnabled(list.isEmpty());
}

}  // namespace clearway::ui
