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
  // Emits robotChanged once if anything changed. A preset's name with other sizes than the
  // preset's is the operator's own robot: "custom".
  void setRobot(const RobotParams& robot);
  // setRobot for a robot asked for from outside (the command line): what is wrong with it, empty
  // when the panel shows it as given. A size the engine refuses or outside the panel's ranges (its
  // boxes would change it silently) is refused and the panel left as it was.
  std::string takeRobot(const RobotParams& robot);
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
