#pragma once

#include <QMainWindow>
#include <memory>

#include "clearway/pose.h"
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
  // The scan's pose (main_window_pose.cpp). A scan whose up direction was only estimated shows
  // nothing traversable until the operator confirms the estimate, picks the floor or types a pose.
  void editScanPose();
  void setScanPose(const PoseRequest& request, PoseSource source);
  void confirmEstimatedUp();
  // "This is the floor" at a point of the 3D view (map frame as the view shows it; the scanner
  // frame when there is no ground): its plane's normal becomes up and the scan is segmented
  // again. Empty on success, else why not (also in the status bar).
  QString pickFloorAt(double x, double y, double z);
  // True while traversable cells are withheld (an estimated up direction, not yet confirmed).
  bool withholdsTraversable() const;
  // "Can it get there?" for a map position: core's planPath from the robot's pose; the path is
  // drawn as footprints in both views. Returns the status bar's answer.
  QString canItGetThere(double map_x, double map_y);
  // What the views show (the result as drawn, withheld cells included).
  const SessionResult& shownResult() const;

  // Acquisitions that did not finish (main_window_recovery.cpp): their journals in the scanner's
  // scans folder are turned into SCAN-recovered.pcd in the background, the last one is opened,
  // and journalsRecovered follows. Nothing happens while a scan is being acquired.
  void recoverInterruptedAcquisitions();
  // How many journals wait for recovery; updates the File menu's action and says so in the
  // status bar.
  int checkUnfinishedJournals();

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
  // A cancelled open or segmentation has been said (in the status bar: no error dialog).
  void cancelShown();
  void exported(const QString& path);
  void journalsRecovered(const QStringList& scans, const QStringList& problems);

 protected:
  void dragEnterEvent(QDragEnterEvent* event) override;
  void dropEvent(QDropEvent* event) override;
  void closeEvent(QCloseEvent* event) override;

 private:
  void buildMenus();
  void addViewToolBar();
  void showResult(const SessionResult& result);
  void showFailure(const QString& reason);
  void showCancelled();
  void clearShown();
  void updateTitle();
  void updateAge();
  void restoreLayout();
  void nudgeRobotWidth(double metres);
  void showPoseAndReach();
  void planGoal();
  // Forgets the goal and takes its path off both views.
  void dropGoal();
  void updateTrustBanner();
  void setUpJournalRecovery();
  int updateRecoverAction();  // the File menu's action only; how many journals wait

  struct Private;
  std::unique_ptr<Private> d_;
};

}  // namespace clearway::ui
