#pragma once

// Robot size: a slider and a spin box per dimension and the presets of the LMF's configurations.
// Each dimension's range is what the engine's validation (SegmentationParams::validate) accepts
// given the other dimensions and the map parameters, so the panel cannot ask for a robot the engine
// refuses. The preset box names the preset only while the robot is that preset, else "custom".

#include <QWidget>
#include <memory>

#include "clearway/segmentation/params.h"

namespace clearway::ui {

class RobotPanel : public QWidget {
  Q_OBJECT

 public:
  explicit RobotPanel(QWidget* parent = nullptr);
  ~RobotPanel() override;

  RobotParams robot() const;
  double maxSlopeDeg() const;
  void setMaxSlopeDeg(double degrees);
  void setRobot(const RobotParams& robot);  // emits robotChanged once if anything changed
  // The parameters the robot is checked against (map resolution etc.); narrows the ranges.
  void setEngineParams(const SegmentationParams& params);
  // The smallest and largest value the engine accepts for a dimension ("robot.width").
  std::pair<double, double> limits(const std::string& key) const;
  QString presetName() const;

 signals:
  void robotChanged(const clearway::RobotParams& robot);
  // The steepest drivable slope changed: ground planes must be chosen again (stages 1-4).
  void maxSlopeChanged(double degrees);

 private:
  struct Private;
  std::unique_ptr<Private> d_;
};

}  // namespace clearway::ui
