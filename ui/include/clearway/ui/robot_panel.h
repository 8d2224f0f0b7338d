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
  void setRobot(const RobotParams& robot);  // emits robotChanged once if anything changed

 signals:
  void robotChanged(const clearway::RobotParams& robot);

 private:
  struct Private;
  std::unique_ptr<Private> d_;
};

}  // namespace clearway::ui
