#pragma once

// The 3D view: the point cloud, the drivable ground coloured by the map, red wall cuboids, orange
// obstacle cubes and the scanner. VTK stays inside scene_view.cpp; without OpenGL (the offscreen
// platform, broken drivers) the view shows a plain message and the rest of the window works.

#include <QWidget>
#include <memory>

#include "clearway/pipeline.h"
#include "clearway/scan.h"

class QImage;

namespace clearway::ui {

class SceneView : public QWidget {
  Q_OBJECT

 public:
  explicit SceneView(QWidget* parent = nullptr);
  ~SceneView() override;

  enum class CameraView { kBehind, kTop, kFront, kSide };
  enum class Layer { kCloud, kGround, kWalls, kObstacles };
  enum class CloudColour { kRemission, kHeight, kClass };

  void setScene(std::shared_ptr<const Scan> scan, std::shared_ptr<const PipelineResult> result);
  // A scan still arriving: only the cloud is replaced; the camera stays where the operator put it
  // (it is placed once, on the first lines).
  void showArrivingScan(std::shared_ptr<const Scan> so_far);
  void resetCamera();
  void setCameraView(CameraView view);
  void setLayerVisible(Layer layer, bool visible);
  bool layerVisible(Layer layer) const;
  void setCloudColour(CloudColour colour);
  // The robot's box standing at a map position (a place the operator picked on the map).
  void showRobotAt(double map_x, double map_y, double yaw_deg);
  // True when a 3D view could be created (an OpenGL context is available).
  bool hasRenderer() const;
  // The last rendered picture (empty without a renderer).
  QImage renderedImage();

  // Creating QVTKOpenGLNativeWidget needs this format set before QApplication exists.
  static void prepareApplication();

 private:
  struct Private;
  std::unique_ptr<Private> d_;
};

}  // namespace clearway::ui
