#pragma once

// The main window's state, shared by main_window.cpp (wiring) and main_window_menus.cpp (menus,
// tool bar, shortcuts).

#include <QDateTime>
#include <QLabel>
#include <QPointF>
#include <QProgressBar>
#include <QPushButton>
#include <QTimer>
#include <optional>

#include "clearway/scan_summary.h"
#include "clearway/ui/main_window.h"
#include "clearway/ui/palette.h"
#include "clearway/ui/segmentation_session.h"

class QAction;
class QDockWidget;

namespace clearway::ui {

class JournalRecovery;
class ScanPanel;

struct MainWindow::Private {
  SegmentationSession* session = nullptr;
  MapView* map = nullptr;
  SceneView* scene = nullptr;
  RobotPanel* robot = nullptr;
  QWidget* trust_bar = nullptr;  // the banner and its buttons
  QLabel* banner = nullptr;
  QPushButton* confirm_up = nullptr;
  QPushButton* pick_floor = nullptr;
  QPushButton* type_pose = nullptr;
  QAction* goal_action = nullptr;
  QAction* floor_action = nullptr;
  QAction* measure_action = nullptr;
  QAction* recover_action = nullptr;
  JournalRecovery* recovery = nullptr;
  // An estimated up direction the operator has not confirmed: nothing traversable is drawn.
  bool withheld = false;
  // The last "Can it get there?" goal (map frame), re-planned when the robot changes, and its
  // answer (kept beside the hover readout, which replaces the status bar's message).
  std::optional<QPointF> goal;
  QString goal_answer;
  ScanPanel* scans = nullptr;
  HardwarePanel* hardware = nullptr;
  std::vector<QDockWidget*> docks;
  SessionResult shown;
  ScanSummary shown_facts;  // summarise(*shown.scan), for the summary refreshed with its age
  QLabel* hover = nullptr;
  QLabel* age = nullptr;
  QProgressBar* progress = nullptr;
  QPushButton* cancel = nullptr;
  QTimer age_timer;
  bool shown_is_previous = false;
  PaletteKind palette = PaletteKind::kColourBlindSafe;
};

// The result with nothing traversable left in it (green, careful, low obstacles and climbable
// stairs become unknown, in the map, on the 3D ground and on the obstacle cubes): what is drawn
// while an estimated up direction waits for the operator (main_window_pose.cpp).
std::shared_ptr<const PipelineResult> withholdTraversable(const PipelineResult& result);

// QSettings keys.
inline const char* const kParamsKey = "segmentation/params";
inline const char* const kGeometryKey = "window/geometry";
inline const char* const kStateKey = "window/state";
inline const char* const kPaletteKey = "view/classicPalette";

}  // namespace clearway::ui
