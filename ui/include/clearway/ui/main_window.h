#pragma once

#include <QMainWindow>
#include <memory>

#include "clearway/segmentation/params.h"

namespace clearway::ui {

class HardwarePanel;
class MapView;
class RobotPanel;
class SceneView;
class SegmentationSession;
struct SessionResult;

// The operator console's main window. It only wires panels and the session together.
class MainWindow : public QMainWindow {
  Q_OBJECT

 public:
  explicit MainWindow(QWidget* parent = nullptr);
  ~MainWindow() override;

  // Loads and segments a scan in the background; the window stays responsive.
  void openScan(const QString& path);
  void browseForScan();
  void editParameters();
  void setRobot(const RobotParams& robot);

  MapView* mapView() const;
  SceneView* sceneView() const;
  HardwarePanel* hardwarePanel() const;
  RobotPanel* robotPanel() const;
  SegmentationSession* session() const;
  // Saves a picture of the whole window; false (with a message on stderr) when it cannot.
  bool saveScreenshot(const QString& path);

 signals:
  // A result (or a failure) has been shown.
  void resultShown(bool trusted);
  void failureShown(const QString& reason);

 protected:
  void dragEnterEvent(QDragEnterEvent* event) override;
  void dropEvent(QDropEvent* event) override;

 private:
  void addViewToolBar();
  void showResult(const SessionResult& result);
  void showFailure(const QString& reason);

  struct Private;
  std::unique_ptr<Private> d_;
};

}  // namespace clearway::ui
