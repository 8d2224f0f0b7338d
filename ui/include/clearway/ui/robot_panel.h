#pragma once

// Robot size: a slider and a spin box per dimension (ranges from the parameter table) and the
// presets of the LMF's configurations.

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

 signals:
  void robotChanged(const clearway::RobotParams& robot);
  // The steepest drivable slope changed: ground planes must be chosen again (stages 1-4).
  void maxSlopeChanged(double degrees);

 private:
  struct Private;
  std::unique_ptr<Private> d_;
};

}  // namespace clearway::ui
