#pragma once

// The main window's state, shared by main_window.cpp (wiring) and main_window_menus.cpp (menus,
// tool bar, shortcuts).

#include <QDateTime>
#include <QLabel>
#include <QProgressBar>
#include <QPushButton>
#include <QTimer>

#include "clearway/ui/main_window.h"
#include "clearway/ui/palette.h"
#include "clearway/ui/segmentation_session.h"

class QDockWidget;

namespace clearway::ui {

class ScanPanel;

struct MainWindow::Private {
  SegmentationSession* session = nullptr;
  MapView* map = nullptr;
  SceneView* scene = nullptr;
  RobotPanel* robot = nullptr;
  QLabel* banner = nullptr;
  ScanPanel* scans = nullptr;
  HardwarePanel* hardware = nullptr;
  std::vector<QDockWidget*> docks;
  SessionResult shown;
  QLabel* hover = nullptr;
  QLabel* age = nullptr;
  QProgressBar* progress = nullptr;
  QPushButton* cancel = nullptr;
  QTimer age_timer;
  bool shown_is_previous = false;
  PaletteKind palette = PaletteKind::kColourBlindSafe;
};

// QSettings keys.
inline const char* const kParamsKey = "segmentation/params";
inline const char* const kGeometryKey = "window/geometry";
inline const char* const kStateKey = "window/state";
inline const char* const kPaletteKey = "view/classicPalette";

}  // namespace clearway::ui
