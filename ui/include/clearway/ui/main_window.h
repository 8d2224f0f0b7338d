#pragma once

#include <QMainWindow>
#include <memory>

#include "clearway/segmentation/params.h"
#include "clearway/ui/export_actions.h"

namespace clearway::ui {

class HardwarePanel;
class MapView;
class RobotPanel;
class SceneView;
class SegmentationSession;
struct SessionResult;

// The operator console's main window. It only wires panels and the session together; menus and
// shortcuts are built in main_window_menus.cpp.
//
// Truth on screen: the views show the result of the scan and robot named in the title bar, or
// nothing. A failed or cancelled open clears them; a new acquisition greys them ("previous scan,
// N min old") until its result is shown.
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
  // Writes an export (the extension is added when missing); empty on success, else the problem,
  // which is also shown. On success the status bar names the file and `exported` is emitted.
  QString exportTo(ExportKind kind, const QString& path, const MapPictureOptions& picture = {});
  // What the views show is now the previous scan (an acquisition started).
  void markShownAsPrevious();
  bool shownIsPrevious() const;

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
  void exported(const QString& path);

 protected:
  void dragEnterEvent(QDragEnterEvent* event) override;
  void dropEvent(QDropEvent* event) override;
  void closeEvent(QCloseEvent* event) override;

 private:
  void buildMenus();
  void addViewToolBar();
  void showResult(const SessionResult& result);
  void showFailure(const QString& reason);
  void clearShown();
  void updateTitle();
  void updateAge();
  void restoreLayout();
  void nudgeRobotWidth(double metres);

  struct Private;
  std::unique_ptr<Private> d_;
};

}  // namespace clearway::ui
