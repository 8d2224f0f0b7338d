// The main window's menus, tool bar and keyboard shortcuts.

#include <QAction>
#include <QActionGroup>
#include <QComboBox>
#include <QDockWidget>
#include <QFileDialog>
#include <QInputDialog>
#include <QMenuBar>
#include <QPushButton>
#include <QSettings>
#include <QStatusBar>
#include <QToolBar>

#include "clearway/ui/hardware_panel.h"
#include "clearway/ui/main_window.h"
#include "clearway/ui/map_view.h"
#include "clearway/ui/scene_view.h"
#include "main_window_private.h"

namespace clearway::ui {
namespace {

// Width +/- steps the robot's width by this much [m].
constexpr double kWidthStep = 0.05;
// The map picture's default scale and the range offered [px per metre].
constexpr double kPictureScale = 40.0, kPictureScaleMin = 5.0, kPictureScaleMax = 400.0;

}  // namespace

void MainWindow::buildMenus() {
  auto* file = menuBar()->addMenu(tr("&File"));
  QAction* open = file->addAction(tr("&Open scan..."), this, &MainWindow::browseForScan);
  open->setShortcut(QKeySequence::Open);
  QAction* previous = file->addAction(tr("&Previous scan in folder"), this, [this] {
    if (auto* button = findChild<QPushButton*>("previousScanButton"); button && button->isEnabled())
      button->click();
  });
  previous->setShortcut(Qt::Key_PageUp);
  QAction* next = file->addAction(tr("&Next scan in folder"), this, [this] {
    if (auto* button = findChild<QPushButton*>("nextScanButton"); button && button->isEnabled())
      button->click();
  });
  next->setShortcut(Qt::Key_PageDown);
  d_->recover_action = file->addAction(tr("&Recover interrupted acquisitions"), this,
                                       &MainWindow::recoverInterruptedAcquisitions);
  d_->recover_action->setObjectName("recoverAction");
  d_->recover_action->setEnabled(false);
  auto* exports = file->addMenu(tr("&Export"));
  const std::tuple<QString, ExportKind, QString> kinds[] = {
      {tr("Map picture with legend and scale (PNG)..."), ExportKind::kMapPicture, "PNG (*.png)"},
      {tr("Map data, one pixel per cell (PNG)..."), ExportKind::kMapPng, "PNG (*.png)"},
      {tr("ROS map (PGM + YAML)..."), ExportKind::kRosMap, "PGM (*.pgm)"},
      {tr("3D scene (PLY)..."), ExportKind::kScenePly, "PLY (*.ply)"},
      {tr("Report (JSON)..."), ExportKind::kReportJson, "JSON (*.json)"},
      {tr("3D view screenshot (PNG)..."), ExportKind::kScreenshot3d, "PNG (*.png)"}};
  for (const auto& [name, kind, filter] : kinds)
    exports->addAction(name, this, [this, kind = kind, filter = filter, name = name] {
      MapPictureOptions picture;
      if (kind == ExportKind::kMapPicture) {
        bool ok = false;
        picture.pixels_per_metre =
            QInputDialog::getDouble(this, name, tr("Scale [pixels per metre]:"), kPictureScale,
                                    kPictureScaleMin, kPictureScaleMax, 0, &ok);
        if (!ok) return;
      }
      const QString path = QFileDialog::getSaveFileName(this, name, {}, filter);
      if (!path.isEmpty()) exportTo(kind, path, picture);
    });
  file->addSeparator();
  file->addAction(tr("&Quit"), this, &QWidget::close)->setShortcut(QKeySequence::Quit);

  auto* scan = menuBar()->addMenu(tr("S&can"));
  QAction* start = scan->addAction(tr("&Scan now"), d_->hardware, &HardwarePanel::startScan);
  start->setShortcut(Qt::Key_F5);
  QAction* cancel = scan->addAction(tr("&Cancel"), this, [this] {
    d_->session->cancel();
    d_->hardware->cancelScan();
  });
  cancel->setShortcut(Qt::Key_Escape);
  scan->addSeparator();
  QAction* type_pose =
      scan->addAction(tr("Type the scan's &pose..."), this, &MainWindow::editScanPose);
  type_pose->setObjectName("typePoseAction");
  type_pose->setShortcut(QKeySequence("Ctrl+Shift+P"));
  QAction* confirm_up = scan->addAction(tr("&Confirm the estimated up direction"), this,
                                        &MainWindow::confirmEstimatedUp);
  confirm_up->setObjectName("confirmUpAction");
  confirm_up->setEnabled(false);  // only while an estimated up direction waits (trust banner)
  scan->addSeparator();
  scan->addAction(tr("Robot &wider"), this, [this] { nudgeRobotWidth(kWidthStep); })
      ->setShortcut(Qt::Key_BracketRight);
  scan->addAction(tr("Robot &narrower"), this, [this] { nudgeRobotWidth(-kWidthStep); })
      ->setShortcut(Qt::Key_BracketLeft);

  auto* view = menuBar()->addMenu(tr("&View"));
  view->setObjectName("viewMenu");
  using View = SceneView::CameraView;
  const std::tuple<QString, View, QKeySequence> cameras[] = {
      {tr("&Operator view (behind the robot)"), View::kBehind, QKeySequence("Ctrl+1")},
      {tr("&Top view (as the map)"), View::kTop, QKeySequence("Ctrl+2")},
      {tr("&Front view"), View::kFront, QKeySequence("Ctrl+3")},
      {tr("&Side view"), View::kSide, QKeySequence("Ctrl+4")}};
  for (const auto& [name, camera, keys] : cameras) {
    QAction* action =
        view->addAction(name, this, [this, camera = camera] { d_->scene->setCameraView(camera); });
    action->setShortcut(keys);
  }
  QAction* fit = view->addAction(tr("&Fit map"), d_->map, &MapView::fit);
  fit->setObjectName("fitAction");
  fit->setShortcut(Qt::Key_F);
  QAction* measure = view->addAction(tr("&Measure distance (two clicks)"));
  measure->setObjectName("measureAction");
  measure->setCheckable(true);
  measure->setShortcut(Qt::Key_M);
  d_->measure_action = measure;
  // The map tools take the next click(s); at most one of them is on.
  QAction* goal = view->addAction(tr("&Can it get there? (click a goal on the map)"));
  goal->setObjectName("goalAction");
  goal->setCheckable(true);
  goal->setShortcut(Qt::Key_G);
  goal->setIconText(tr("Can it get there?"));
  d_->goal_action = goal;
  QAction* floor = view->addAction(tr("This is the f&loor (click it in the 3D view)"));
  floor->setObjectName("floorAction");
  floor->setCheckable(true);
  floor->setShortcut(Qt::Key_L);
  floor->setIconText(tr("This is the floor"));
  d_->floor_action = floor;
  connect(measure, &QAction::toggled, this, [this](bool on) {
    if (on) {
      d_->goal_action->setChecked(false);
      d_->floor_action->setChecked(false);
    }
    d_->map->setMeasuring(on);
    d_->scene->setMeasuring(on);
  });
  connect(goal, &QAction::toggled, this, [this](bool on) {
    if (!on) return;
    d_->measure_action->setChecked(false);
    d_->floor_action->setChecked(false);
    statusBar()->showMessage(tr("Can it get there? Click the goal on the map."));
  });
  connect(floor, &QAction::toggled, this, [this](bool on) {
    if (!on) return;
    d_->measure_action->setChecked(false);
    d_->goal_action->setChecked(false);
    statusBar()->showMessage(tr("This is the floor: click the floor in the 3D view."));
  });
  view->addSeparator();
  auto* layers = view->addMenu(tr("&Layers"));
  using Layer = SceneView::Layer;
  const std::tuple<QString, Layer, QKeySequence> layer_list[] = {
      {tr("Cloud"), Layer::kCloud, QKeySequence("Ctrl+Shift+1")},
      {tr("Ground"), Layer::kGround, QKeySequence("Ctrl+Shift+2")},
      {tr("Walls"), Layer::kWalls, QKeySequence("Ctrl+Shift+3")},
      {tr("Obstacles"), Layer::kObstacles, QKeySequence("Ctrl+Shift+4")},
      {tr("Ceiling"), Layer::kCeiling, QKeySequence("Ctrl+Shift+5")},
      {tr("Grid and axes"), Layer::kGrid, QKeySequence("Ctrl+Shift+6")}};
  for (const auto& [name, layer, keys] : layer_list) {
    QAction* action = layers->addAction(name);
    action->setObjectName("layer" + QString(name).remove(' '));
    action->setCheckable(true);
    action->setChecked(true);
    action->setShortcut(keys);
    connect(action, &QAction::toggled, this,
            [this, layer = layer](bool on) { d_->scene->setLayerVisible(layer, on); });
  }
  QAction* classic = view->addAction(tr("&Classic colours (not colour-blind safe)"));
  classic->setObjectName("classicPaletteAction");
  classic->setCheckable(true);
  connect(classic, &QAction::toggled, this, [this](bool on) {
    d_->palette = on ? PaletteKind::kClassic : PaletteKind::kColourBlindSafe;
    QSettings().setValue(kPaletteKey, on);
    d_->map->setPaletteKind(d_->palette);
    d_->scene->setPaletteKind(d_->palette);
  });
  classic->setChecked(QSettings().value(kPaletteKey, false).toBool());
  view->addSeparator();
  auto* panels = view->addMenu(tr("&Panels"));
  for (QDockWidget* dock : d_->docks)
    panels->addAction(dock->toggleViewAction());

  menuBar()
      ->addMenu(tr("&Settings"))
      ->addAction(tr("&Parameters..."), this, &MainWindow::editParameters);
}

void MainWindow::addViewToolBar() {
  auto* bar = addToolBar(tr("View"));
  bar->setObjectName("viewToolBar");
  using View = SceneView::CameraView;
  const std::pair<QString, View> views[] = {{tr("Operator"), View::kBehind},
                                            {tr("Top"), View::kTop},
                                            {tr("Front"), View::kFront},
                                            {tr("Side"), View::kSide}};
  for (const auto& [name, view] : views)
    bar->addAction(name, this, [this, view = view] { d_->scene->setCameraView(view); });
  bar->addSeparator();
  bar->addAction(findChild<QAction*>("fitAction"));
  bar->addAction(findChild<QAction*>("measureAction"));
  bar->addAction(d_->goal_action);
  bar->addAction(d_->floor_action);
  bar->addSeparator();
  auto* colour = new QComboBox(bar);
  colour->setObjectName("cloudColour");
  colour->addItems({tr("Cloud: remission"), tr("Cloud: height"), tr("Cloud: class")});
  connect(colour, qOverload<int>(&QComboBox::activated), this,
          [this](int index) { d_->scene->setCloudColour(SceneView::CloudColour(index)); });
  bar->addWidget(colour);
  bar->toggleViewAction()->setText(tr("Tool bar"));
}

}  // namespace clearway::ui
