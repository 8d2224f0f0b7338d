#pragma once

// The 3D view, in the map frame (x forward from the scanner's foot, y left, z up, ground at z = 0):
// the point cloud, the ceiling as a layer of its own, the drivable ground coloured by the map,
// upright wall boxes, obstacle cubes, a metre grid with labels, the map axes, the robot at its pose
// with its heading, a planned path, a legend. Cameras: the operator's view (behind and above the
// robot, looking where the scanner looked), an orthographic top view aligned with the 2D map
// (map +y up on screen, ceiling hidden), front and side; all framed on the robust extent of the
// cloud (percentiles, not stray returns). VTK's own key bindings are off; a click (no drag) picks
// a point, in measuring mode two clicks measure a distance. VTK stays inside scene_*.cpp; without
// OpenGL (the offscreen platform) the view shows a plain message and the rest of the window works.

#include <QWidget>
#include <array>
#include <memory>
#include <vector>

#include "clearway/pipeline.h"
#include "clearway/scan.h"
#include "clearway/ui/map_drawing.h"
#include "clearway/ui/palette.h"

class QImage;

namespace clearway::ui {

class SceneView : public QWidget {
  Q_OBJECT

 public:
  explicit SceneView(QWidget* parent = nullptr);
  ~SceneView() override;

  enum class CameraView { kBehind, kTop, kFront, kSide };
  enum class Layer { kCloud, kGround, kWalls, kObstacles, kCeiling, kGrid };
  enum class CloudColour { kRemission, kHeight, kClass };

  void setScene(std::shared_ptr<const Scan> scan, std::shared_ptr<const PipelineResult> result);
  // Shows nothing but the hint to open or acquire a scan.
  void clearScene();
  // A scan still arriving: only the cloud is replaced; the camera stays where the operator put it
  // (it is placed once, on the first lines).
  void showArrivingScan(std::shared_ptr<const Scan> so_far);
  // The operator's view.
  void resetCamera();
  void setCameraView(CameraView view);
  CameraView cameraView() const;
  bool isOrthographic() const;
  void setLayerVisible(Layer layer, bool visible);
  bool layerVisible(Layer layer) const;
  void setCloudColour(CloudColour colour);
  void setPaletteKind(PaletteKind palette);
  // Where the robot stands (map frame). Until the engine reports a pose, the scanner's foot.
  void setRobotPose(double x, double y, double yaw);
  // The engine's "Can it get there?" path; empty hides it.
  void setPath(std::vector<PathPose> path);
  // Per map cell, 1 where the robot can get to; free ground out of reach is darkened.
  void setReachable(std::vector<std::uint8_t> reachable);
  // The robot's box standing at a map position the operator selected (yaw NaN: fits nowhere).
  void showRobotAt(double map_x, double map_y, double yaw_deg);
  // A note over the view while the shown scene is old (empty: none).
  void setStale(const QString& note);
  // The next two clicks measure a distance instead of picking.
  void setMeasuring(bool on);
  // Picks at a widget position as a click would (tests, keyboard); false when nothing is there.
  bool pickAt(QPoint widget_position);
  // x0, x1, y0, y1, z0, z1 of the cloud between its 1st and 99th percentiles (map frame).
  std::array<double, 6> robustBounds() const;
  // The scan the view shows (or was given, without a renderer); null when cleared.
  std::shared_ptr<const Scan> shownScan() const;
  // True when a 3D view could be created (an OpenGL context is available).
  bool hasRenderer() const;
  // The last rendered picture (empty without a renderer).
  QImage renderedImage();

  // Creating QVTKOpenGLNativeWidget needs this format set before QApplication exists.
  static void prepareApplication();

 signals:
  // A picked point (map frame) and what is there in words.
  void pointPicked(double x, double y, double z, const QString& description);
  void measured(double metres);

 private:
  void rebuild(bool keep_camera);
  void rebuildOverlays();
  void applyLayerVisibility();
  void render();
  bool handleClick(int x, int y);
  struct Private;
  std::unique_ptr<Private> d_;
};

}  // namespace clearway::ui
