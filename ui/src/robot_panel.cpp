#include "clearway/ui/robot_panel.h"

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QSignalBlocker>
#include <QSlider>
#include <cmath>
#include <cstdio>

namespace clearway::ui {
namespace {

// Slider steps are centimetres; sliders stop at 4 m, so that a centimetre is still a step a hand
// can make. The spin boxes take the parameter table's whole range, as the CLI does.
constexpr double kSliderScale = 100.0;
constexpr double kSliderMaximum = 4.0;
const char* const kCustom = "custom";

const ParameterInfo& infoFor(const std::vector<ParameterInfo>& infos, const std::string& key) {
  for (const ParameterInfo& info : infos)
    if (info.key == key) return info;
  throw std::invalid_argument(key);
}

}  // namespace

struct RobotPanel::Private {
  struct Dimension {
    std::string key;
    QSlider* slider = nullptr;
    QDoubleSpinBox* spin = nullptr;
  };
  std::vector<Dimension> dimensions;
  QComboBox* presets = nullptr;
  QDoubleSpinBox* max_slope = nullptr;
  std::string name = "custom";
  SegmentationParams engine;  // the robot is checked against these

  // The engine's first reason to refuse the robot of `params`, empty when it takes it (reasons
  // about other parameters are another panel's).
  static std::string robotReason(const SegmentationParams& params) {
    for (const std::string& reason : params.validate())
      if (reason.find("robot") != std::string::npos) return reason;
    return {};
  }

  // Candidate values of `key` on the slider's grid the engine accepts with the other dimensions
  // as they are; the dimension's own parameter-table range when none is (another problem).
  std::pair<double, double> accepted(const std::string& key, const RobotParams& robot) const {
    const ParameterInfo info = infoFor(describeParameters(), key);
    const double top = std::min(info.maximum, kSliderMaximum);
    std::pair<double, double> range{top, info.minimum};
    SegmentationParams params = engine;
    params.robot = robot;
    for (int step = int(std::ceil(info.minimum * kSliderScale));
         step <= int(std::floor(top * kSliderScale)); ++step) {
      setParameterValue(params, key, step / kSliderScale);
      if (!robotReason(params).empty()) continue;
      range.first = std::min(range.first, step / kSliderScale);
      range.second = std::max(range.second, step / kSliderScale);
    }
    if (range.first > range.second) return {info.minimum, top};
    return range;
  }

  void updateLimits(const RobotParams& robot) {
    for (const Dimension& dimension : dimensions) {
      const auto [low, high] = accepted(dimension.key, robot);
      const QSignalBlocker block_spin(dimension.spin), block_slider(dimension.slider);
      dimension.spin->setRange(low, high);
      dimension.slider->setRange(int(std::lround(low * kSliderScale)),
                                 int(std::lround(high * kSliderScale)));
      dimension.slider->setValue(int(std::lround(dimension.spin->value() * kSliderScale)));
    }
  }

  void showPresetName() {
    const int index = presets->findText(QString::fromStdString(name));
    presets->setCurrentIndex(index >= 0 ? index : presets->findText(kCustom));
  }
};

RobotPanel::RobotPanel(QWidget* parent) : QWidget(parent), d_(std::make_unique<Private>()) {
  setObjectName("robotPanel");
  auto* form = new QFormLayout(this);
  d_->presets = new QComboBox(this);
  d_->presets->setObjectName("robotPresets");
  for (const RobotParams& preset : robotPresets())
    d_->presets->addItem(QString::fromStdString(preset.name));
  d_->presets->addItem(kCustom);
  form->addRow(tr("Preset"), d_->presets);

  const auto infos = describeParameters();
  const std::pair<const char*, QString> rows[] = {{"robot.width", tr("Width [m]")},
                                                  {"robot.length", tr("Length [m]")},
                                                  {"robot.height", tr("Height [m]")},
                                                  {"robot.max_step", tr("Step [m]")}};
  for (const auto& [key, label] : rows) {
    const ParameterInfo& info = infoFor(infos, key);
    Private::Dimension dimension{key};
    dimension.slider = new QSlider(Qt::Horizontal, this);
    dimension.slider->setRange(
        int(std::ceil(info.minimum * kSliderScale)),
        int(std::floor(std::min(info.maximum, kSliderMaximum) * kSliderScale)));
    dimension.spin = new QDoubleSpinBox(this);
    dimension.spin->setRange(info.minimum, info.maximum);
    dimension.spin->setDecimals(2);
    dimension.spin->setSingleStep(0.01);
    dimension.spin->setToolTip(QString::fromStdString(info.description));
    const QString name = QString::fromStdString(key).replace('.', '_');
    dimension.slider->setObjectName(name + "_slider");
    dimension.spin->setObjectName(name + "_spin");
    auto* row = new QHBoxLayout;
    row->addWidget(dimension.slider, 1);
    row->addWidget(dimension.spin);
    form->addRow(label, row);
    d_->dimensions.push_back(dimension);
  }

  for (const auto& dimension : d_->dimensions) {
    connect(dimension.slider, &QSlider::valueChanged, this,
            [this, spin = dimension.spin](int value) { spin->setValue(value / kSliderScale); });
    connect(dimension.spin, qOverload<double>(&QDoubleSpinBox::valueChanged), this,
            [this, slider = dimension.slider](double value) {
              const QSignalBlocker block(slider);
              slider->setValue(int(std::lround(value * kSliderScale)));
              d_->name = kCustom;
              d_->showPresetName();
              d_->updateLimits(robot());
              emit robotChanged(robot());
            });
  }
  const ParameterInfo& slope = infoFor(infos, "ground.max_slope_deg");
  d_->max_slope = new QDoubleSpinBox(this);
  d_->max_slope->setObjectName("ground_max_slope_deg_spin");
  d_->max_slope->setRange(slope.minimum, slope.maximum);
  d_->max_slope->setDecimals(0);
  d_->max_slope->setValue(slope.default_value);
  d_->max_slope->setToolTip(QString::fromStdString(slope.description));
  // Only when editing ends: each change re-segments the scan.
  d_->max_slope->setKeyboardTracking(false);
  form->addRow(tr("Max slope [deg]"), d_->max_slope);
  connect(d_->max_slope, qOverload<double>(&QDoubleSpinBox::valueChanged), this,
          &RobotPanel::maxSlopeChanged);

  connect(d_->presets, qOverload<int>(&QComboBox::activated), this, [this](int index) {
    if (std::size_t(index) < robotPresets().size())
      setRobot(robotPresets()[std::size_t(index)]);
    else
      d_->showPresetName();  // "custom" is what the sliders make, not a robot to load
  });
  setRobot(robotPresets().front());
}

RobotPanel::~RobotPanel() = default;

double RobotPanel::maxSlopeDeg() const {
  return d_->max_slope->value();
}

void RobotPanel::setMaxSlopeDeg(double degrees) {
  const QSignalBlocker block(d_->max_slope);
  d_->max_slope->setValue(degrees);
}

RobotParams RobotPanel::robot() const {
  // The panel edits the size; the rest of the robot (the scanner's mounting, its stair ability)
  // comes with the engine's parameters (Settings > Parameters) and must survive a slider move.
  SegmentationParams params = d_->engine;
  for (const auto& dimension : d_->dimensions)
    setParameterValue(params, dimension.key, dimension.spin->value());
  params.robot.name = d_->name;
  return params.robot;
}

void RobotPanel::setRobot(const RobotParams& given) {
  RobotParams robot = given;
  robot.name = presetOrCustomName(robot);
  SegmentationParams params;
  params.robot = robot;
  bool changed = false;
  for (const auto& dimension : d_->dimensions) {
    const double value = parameterValue(params, dimension.key);
    if (std::abs(dimension.spin->value() - value) < 1e-9) continue;
    const QSignalBlocker block_spin(dimension.spin), block_slider(dimension.slider);
    dimension.spin->setValue(value);
    dimension.slider->setValue(int(std::lround(value * kSliderScale)));
    changed = true;
  }
  d_->name = robot.name;
  d_->showPresetName();
  d_->updateLimits(this->robot());
  if (changed) emit robotChanged(this->robot());
}

std::string RobotPanel::takeRobot(const RobotParams& robot) {
  SegmentationParams params = d_->engine;
  params.robot = robot;
  if (std::string reason = Private::robotReason(params); !reason.empty()) return reason;
  // Each size against the range the panel takes with the robot's other sizes.
  for (const Private::Dimension& dimension : d_->dimensions) {
    const double value = parameterValue(params, dimension.key);
    const auto [low, high] = d_->accepted(dimension.key, robot);
    if (value < low - 1e-9 || value > high + 1e-9) {
      char range[96];
      std::snprintf(range, sizeof range, " from %.2f to %.2f m with its other sizes, not %g m", low,
                    high, value);
      return "the console takes " + dimension.key + range;
    }
  }
  setRobot(robot);
  return {};
}

void RobotPanel::setEngineParams(const SegmentationParams& params) {
  d_->engine = params;
  d_->updateLimits(robot());
}

std::pair<double, double> RobotPanel::limits(const std::string& key) const {
  for (const auto& dimension : d_->dimensions)
    if (dimension.key == key) return {dimension.spin->minimum(), dimension.spin->maximum()};
  throw std::invalid_argument(key);
}

QString RobotPanel::presetName() const {
  return d_->presets->currentText();
}

}  // namespace clearway::ui
