#include "clearway/ui/main_window.h"

#include <QAction>
#include <QApplication>
#include <QComboBox>
#include <QDockWidget>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QFileDialog>
#include <QFileInfo>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QMimeData>
#include <QProgressBar>
#include <QPushButton>
#include <QSettings>
#include <QSplitter>
#include <QStatusBar>
#include <QToolBar>
#include <QVBoxLayout>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "clearway/scan_summary.h"
#include "clearway/ui/export_actions.h"
#include "clearway/ui/hardware_panel.h"
#include "clearway/ui/map_view.h"
#include "clearway/ui/parameters_dialog.h"
#include "clearway/ui/robot_panel.h"
#include "clearway/ui/scan_panel.h"
#include "clearway/ui/scene_view.h"
#include "clearway/ui/segmentation_session.h"

namespace clearway::ui {

namespace {
const char* const kParamsKey = "segmentation/params";
}  // namespace

struct MainWindow::Private {
  SegmentationSession* session = nullptr;
  MapView* map = nullptr;
  SceneView* scene = nullptr;
  RobotPanel* robot = nullptr;
  QLabel* banner = nullptr;
  ScanPanel* scans = nullptr;
  HardwarePanel* hardware = nullptr;
  SessionResult shown;
  QLabel* timings = nullptr;
  QLabel* hover = nullptr;
  QProgressBar* progress = nullptr;
  QPushButton* cancel = nullptr;
};

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent), d_(std::make_unique<Private>()) {
  setObjectName("mainWindow");
  setWindowTitle(tr("Clearway"));
  d_->session = new SegmentationSession(this);

  // Centre: the trust banner over the map.
  auto* centre = new QWidget(this);
  auto* layout = new QVBoxLayout(centre);
  layout->setContentsMargins(0, 0, 0, 0);
  d_->banner = new QLabel(centre);
  d_->banner->setObjectName("trustBanner");
  d_->banner->setWordWrap(true);
  d_->banner->setStyleSheet(
      "QLabel { background: #b71c1c; color: white; padding: 8px; font-weight: bold; }");
  d_->banner->hide();
  auto* views = new QSplitter(Qt::Horizontal, centre);
  d_->scene = new SceneView(views);
  d_->map = new MapView(views);
  views->addWidget(d_->scene);
  views->addWidget(d_->map);
  views->setSizes({600, 600});
  layout->addWidget(d_->banner);
  layout->addWidget(views, 1);
  setCentralWidget(centre);

  // Right: robot and scan panels.
  d_->robot = new RobotPanel(this);
  auto* robot_dock = new QDockWidget(tr("Robot"), this);
  robot_dock->setObjectName("robotDock");
  robot_dock->setWidget(d_->robot);
  addDockWidget(Qt::RightDockWidgetArea, robot_dock);
  d_->scans = new ScanPanel(this);
  auto* scan_dock = new QDockWidget(tr("Scan"), this);
  scan_dock->setObjectName("scanDock");
  scan_dock->setWidget(d_->scans);
  addDockWidget(Qt::RightDockWidgetArea, scan_dock);
  d_->hardware = new HardwarePanel(this);
  auto* hardware_dock = new QDockWidget(tr("Scanner"), this);
  hardware_dock->setObjectName("hardwareDock");
  hardware_dock->setWidget(d_->hardware);
  addDockWidget(Qt::RightDockWidgetArea, hardware_dock);
  tabifyDockWidget(scan_dock, hardware_dock);
  scan_dock->raise();

  // Bottom: hover readout, stage timings, progress and cancel.
  d_->hover = new QLabel(this);
  d_->timings = new QLabel(this);
  d_->timings->setObjectName("timings");
  d_->progress = new QProgressBar(this);
  d_->progress->setObjectName("progress");
  d_->progress->setMaximumWidth(160);
  d_->progress->hide();
  d_->cancel = new QPushButton(tr("Cancel"), this);
  d_->cancel->setObjectName("cancelButton");
  d_->cancel->hide();
  statusBar()->addWidget(d_->hover, 1);
  statusBar()->addPermanentWidget(d_->timings);
  statusBar()->addPermanentWidget(d_->progress);
  statusBar()->addPermanentWidget(d_->cancel);

  auto* file = menuBar()->addMenu(tr("&File"));
  QAction* open = file->addAction(tr("&Open scan..."), this, &MainWindow::browseForScan);
  open->setShortcut(QKeySequence::Open);
  auto* exports = file->addMenu(tr("&Export"));
  const std::tuple<QString, ExportKind, QString> kinds[] = {
      {tr("Map image (PNG)..."), ExportKind::kMapPng, "PNG (*.png)"},
      {tr("ROS map (PGM + YAML)..."), ExportKind::kRosMap, "PGM (*.pgm)"},
      {tr("3D scene (PLY)..."), ExportKind::kScenePly, "PLY (*.ply)"},
      {tr("Report (JSON)..."), ExportKind::kReportJson, "JSON (*.json)"},
      {tr("3D view screenshot (PNG)..."), ExportKind::kScreenshot3d, "PNG (*.png)"}};
  for (const auto& [name, kind, filter] : kinds)
    exports->addAction(name, this, [this, kind = kind, filter = filter, name = name] {
      const QString path = QFileDialog::getSaveFileName(this, name, {}, filter);
      if (path.isEmpty()) return;
      const QString problem = exportResult(kind, d_->shown, d_->session->params(), path, d_->scene);
      if (!problem.isEmpty()) showFailure(problem);
    });
  file->addSeparator();
  file->addAction(tr("&Quit"), this, &QWidget::close)->setShortcut(QKeySequence::Quit);
  menuBar()
      ->addMenu(tr("&Settings"))
      ->addAction(tr("&Parameters..."), this, &MainWindow::editParameters);

  addViewToolBar();
  connect(d_->map, &MapView::clicked, this, [this](double x, double y) {
    const auto yaw = d_->map->yawAt(x, y);
    d_->scene->showRobotAt(x, y, yaw);
  });
  connect(d_->robot, &RobotPanel::robotChanged, d_->session, &SegmentationSession::setRobot);
  connect(d_->robot, &RobotPanel::maxSlopeChanged, this, [this](double degrees) {
    SegmentationParams params = d_->session->params();
    params.ground.max_slope_deg = degrees;
    d_->session->setParams(params);
    if (!d_->shown.scan_path.isEmpty()) openScan(d_->shown.scan_path);
  });
  connect(d_->scans, &ScanPanel::openRequested, this, &MainWindow::openScan);
  // Scan-and-stop: a saved acquisition is segmented and shown at once.
  connect(d_->hardware, &HardwarePanel::scanSaved, this, [this](const QString& path) {
    openScan(path);
    connect(d_->hardware, &HardwarePanel::linesArrived, d_->scene, &SceneView::showArrivingScan);
  });
  connect(d_->scans, &ScanPanel::browseRequested, this, &MainWindow::browseForScan);
  setAcceptDrops(true);
  connect(d_->cancel, &QPushButton::clicked, d_->session, &SegmentationSession::cancel);
  connect(d_->session, &SegmentationSession::progress, this,
          [this](int percent, const QString& what) {
            d_->progress->setValue(percent);
            d_->progress->setFormat(what + " %p%");
          });
  connect(d_->session, &SegmentationSession::busyChanged, this, [this](bool busy) {
    d_->progress->setVisible(busy);
    d_->cancel->setVisible(busy);
  });
  connect(d_->session, &SegmentationSession::resultReady, this, &MainWindow::showResult);
  connect(d_->session, &SegmentationSession::failed, this, &MainWindow::showFailure);
  connect(d_->map, &MapView::hovered, this, [this](double x, double y, const QString& description) {
    d_->hover->setText(
        tr("x %1 m, y %2 m: %3").arg(x, 0, 'f', 2).arg(y, 0, 'f', 2).arg(description));
  });
  // Parameters saved by an earlier session (QSettings), then the robot panel's robot.
  SegmentationParams params;
  const QString saved = QSettings().value(kParamsKey).toString();
  if (!saved.isEmpty()) {
    try {
      params = paramsFromJson(nlohmann::json::parse(saved.toStdString()));
    } catch (const std::exception&) {
      params = {};  // unreadable settings: the defaults
    }
  }
  params.robot = d_->robot->robot();
  d_->robot->setMaxSlopeDeg(params.ground.max_slope_deg);
  d_->session->setParams(params);
  resize(1200, 800);
}

MainWindow::~MainWindow() = default;

void MainWindow::editParameters() {
  auto* dialog = new ParametersDialog(d_->session->params(), this);
  dialog->setAttribute(Qt::WA_DeleteOnClose);
  connect(dialog, &QDialog::accepted, this, [this, dialog] {
    const SegmentationParams params = dialog->params();
    QSettings().setValue(kParamsKey, QString::fromStdString(toJson(params).dump()));
    d_->robot->setRobot(params.robot);
    d_->robot->setMaxSlopeDeg(params.ground.max_slope_deg);
    d_->session->setParams(params);
    // Stages 1-4 depend on the parameters too: segment the scan again.
    if (!d_->shown.scan_path.isEmpty()) openScan(d_->shown.scan_path);
  });
  dialog->open();
}

void MainWindow::browseForScan() {
  const QString path = QFileDialog::getOpenFileName(
      this, tr("Open scan"), {},
      tr("Scans (*.pcd *.ply *.xyz *.txt *.dat *.asc *.bin *.3d);;All files (*)"));
  if (!path.isEmpty()) openScan(path);
}

void MainWindow::dragEnterEvent(QDragEnterEvent* event) {
  const auto urls = event->mimeData()->urls();
  if (urls.size() == 1 && urls.first().isLocalFile() &&
      ScanPanel::isScanFile(urls.first().toLocalFile()))
    event->acceptProposedAction();
}

void MainWindow::dropEvent(QDropEvent* event) {
  const auto urls = event->mimeData()->urls();
  if (!urls.isEmpty() && urls.first().isLocalFile()) openScan(urls.first().toLocalFile());
}

void MainWindow::addViewToolBar() {
  auto* bar = addToolBar(tr("View"));
  bar->setObjectName("viewToolBar");
  using View = SceneView::CameraView;
  const std::pair<QString, View> views[] = {{tr("Reset view"), View::kBehind},
                                            {tr("Top"), View::kTop},
                                            {tr("Front"), View::kFront},
                                            {tr("Side"), View::kSide}};
  for (const auto& [name, view] : views)
    bar->addAction(name, this, [this, view = view] { d_->scene->setCameraView(view); });
  bar->addSeparator();
  using Layer = SceneView::Layer;
  const std::pair<QString, Layer> layers[] = {{tr("Cloud"), Layer::kCloud},
                                              {tr("Ground"), Layer::kGround},
                                              {tr("Walls"), Layer::kWalls},
                                              {tr("Obstacles"), Layer::kObstacles}};
  for (const auto& [name, layer] : layers) {
    QAction* action = bar->addAction(name);
    action->setObjectName("layer" + name);
    action->setCheckable(true);
    action->setChecked(true);
    connect(action, &QAction::toggled, this,
            [this, layer = layer](bool on) { d_->scene->setLayerVisible(layer, on); });
  }
  auto* colour = new QComboBox(bar);
  colour->setObjectName("cloudColour");
  colour->addItems({tr("Cloud: remission"), tr("Cloud: height"), tr("Cloud: class")});
  connect(colour, qOverload<int>(&QComboBox::activated), this,
          [this](int index) { d_->scene->setCloudColour(SceneView::CloudColour(index)); });
  bar->addWidget(colour);
}

void MainWindow::openScan(const QString& path) {
  statusBar()->showMessage(tr("Loading %1 ...").arg(QFileInfo(path).fileName()));
  d_->session->openScan(path);
}

void MainWindow::setRobot(const RobotParams& robot) {
  d_->robot->setRobot(robot);
}
HardwarePanel* MainWindow::hardwarePanel() const {
  return d_->hardware;
}
SceneView* MainWindow::sceneView() const {
  return d_->scene;
}
MapView* MainWindow::mapView() const {
  return d_->map;
}
RobotPanel* MainWindow::robotPanel() const {
  return d_->robot;
}
SegmentationSession* MainWindow::session() const {
  return d_->session;
}

void MainWindow::showResult(const SessionResult& result) {
  const PipelineResult& pipeline = *result.result;
  d_->shown = result;
  d_->map->setResult(result.result);
  // An untrusted result still shows the cloud, but its scene has no ground and no boxes.
  d_->scene->setScene(result.scan, result.result);
  // The safety rule: when the result cannot be trusted, say so and show nothing traversable.
  d_->banner->setVisible(!pipeline.trusted());
  d_->banner->setText(tr("Nothing is shown as traversable: %1")
                          .arg(QString::fromStdString(pipeline.analysis.reason)));
  d_->scans->setCurrent(result.scan_path, QString::fromStdString(toText(summarise(*result.scan))));
  QStringList stages;
  for (const StageTiming& stage : pipeline.timings)
    stages << QString("%1 %2")
                  .arg(QString::fromStdString(stage.stage))
                  .arg(stage.milliseconds, 0, 'f', 1);
  d_->timings->setText(
      tr("%1 | total %2 ms").arg(stages.join(", ")).arg(pipeline.total_ms, 0, 'f', 1));
  statusBar()->showMessage(QFileInfo(result.scan_path).fileName(), 5000);
  emit resultShown(pipeline.trusted());
}

void MainWindow::showFailure(const QString& reason) {
  statusBar()->showMessage(tr("Failed: %1").arg(reason));
  // Window-modal, not application-modal: nothing waits on it.
  auto* box = new QMessageBox(QMessageBox::Critical, tr("Clearway"), reason, QMessageBox::Ok, this);
  box->setObjectName("errorDialog");
  box->setAttribute(Qt::WA_DeleteOnClose);
  box->open();
  emit failureShown(reason);
}

bool MainWindow::saveScreenshot(const QString& path) {
  const QPixmap picture = grab();
  if (picture.isNull() || !picture.save(path)) {
    std::fprintf(stderr, "clearway: cannot save the screenshot to %s\n", qPrintable(path));
    return false;
  }
  return true;
}

}  // namespace clearway::ui
