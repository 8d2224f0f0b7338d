#include "clearway/ui/main_window.h"

#include <QAction>
#include <QApplication>
#include <QCloseEvent>
#include <QDockWidget>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QFileDialog>
#include <QFileInfo>
#include <QHBoxLayout>
#include <QMessageBox>
#include <QMimeData>
#include <QScreen>
#include <QScrollArea>
#include <QScrollBar>
#include <QSettings>
#include <QSplitter>
#include <QStatusBar>
#include <QVBoxLayout>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "clearway/scan_summary.h"
#include "clearway/ui/hardware_panel.h"
#include "clearway/ui/map_drawing.h"
#include "clearway/ui/map_view.h"
#include "clearway/ui/parameters_dialog.h"
#include "clearway/ui/pose_dialog.h"
#include "clearway/ui/robot_panel.h"
#include "clearway/ui/scan_panel.h"
#include "clearway/ui/scene_view.h"
#include "main_window_private.h"

namespace clearway::ui {
namespace {

// The first window takes this share of the screen's free area, at most kDefaultSize: it fits
// 1366x768 with the status bar and every panel on screen.
constexpr double kScreenShare = 0.92;
const QSize kDefaultSize(1400, 860);
// The age of the shown scan is refreshed this often [ms].
constexpr int kAgeRefreshMs = 15'000;

QString ageInWords(const QDateTime& time) {
  const qint64 seconds = time.secsTo(QDateTime::currentDateTime());
  if (seconds < 60) return QObject::tr("less than a minute old");
  if (seconds < 3600) return QObject::tr("%1 min old").arg(seconds / 60);
  if (seconds < 86400) return QObject::tr("%1 h old").arg(seconds / 3600);
  return QObject::tr("%1 days old").arg(seconds / 86400);
}

// A side panel's scroll area: it scrolls up and down, never sideways. It is at least as wide as
// the panel's narrowest layout and the scroll bar beside it (a panel one scroll bar wider than its
// dock scrolled both ways at 1024 x 600), following the panel as it changes (a scanner device's
// fields).
class PanelScrollArea : public QScrollArea {
 public:
  using QScrollArea::QScrollArea;

  QSize minimumSizeHint() const override {
    QSize size = QScrollArea::minimumSizeHint();
    if (widget())
      size.setWidth(std::max(size.width(), widget()->minimumSizeHint().width() +
                                               verticalScrollBar()->sizeHint().width() +
                                               2 * frameWidth()));
    return size;
  }
  QSize sizeHint() const override {
    return QScrollArea::sizeHint().expandedTo(QSize(minimumSizeHint().width(), 0));
  }

 protected:
  bool eventFilter(QObject* watched, QEvent* event) override {
    if (watched == widget() && event->type() == QEvent::LayoutRequest) updateGeometry();
    return QScrollArea::eventFilter(watched, event);
  }
};

QDockWidget* dockFor(QMainWindow* window, QWidget* panel, const QString& title,
                     const QString& name) {
  // Panels scroll rather than push the window beyond a small screen.
  auto* scroll = new PanelScrollArea(window);
  scroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
  scroll->setWidget(panel);
  scroll->setWidgetResizable(true);
  scroll->setFrameShape(QFrame::NoFrame);
  auto* dock = new QDockWidget(title, window);
  dock->setObjectName(name);
  dock->setWidget(scroll);
  return dock;
}

// The scan in words for the Scan panel, then the raw facts for Details.
// `facts`: summarise(*result.scan), worked out once per scan (every point is looked at).
QString humanSummary(const SessionResult& result, const ScanSummary& facts) {
  QString text = QObject::tr("<b>%1</b><br>%2 points in %3 scan lines")
                     .arg(QFileInfo(result.scan_path).fileName().toHtmlEscaped())
                     .arg(QLocale().toString(qulonglong(facts.valid_points)))
                     .arg(facts.scan_lines);
  // Only acquisition's own record says when the scan was taken; a file's time says when it was
  // saved (or copied).
  if (result.scan_time.isValid())
    text += (result.scan_time_recorded ? QObject::tr("<br>Taken %1 (%2)")
                                       : QObject::tr("<br>File saved %1 (%2)"))
                .arg(QLocale().toString(result.scan_time, QLocale::ShortFormat))
                .arg(ageInWords(result.scan_time));
  const PipelineResult& pipeline = *result.result;
  const ScanAnalysis& analysis = *pipeline.analysis;
  text += QObject::tr("<br>Pose: %1")
              .arg(poseSourceInWords(analysis.pose_source, analysis.up_confidence).toHtmlEscaped());
  if (analysis.pose_source == PoseSource::kSidecar)
    text += QObject::tr(" (%1)").arg(
        QFileInfo(QString::fromStdString(result.pose.detail)).fileName().toHtmlEscaped());
  text += pipeline.trusted()
              ? QObject::tr("<br>Ground found; map of %1 × %2 m at %3 cm cells.")
                    .arg(pipeline.map.grid.width * pipeline.map.grid.resolution, 0, 'f', 1)
                    .arg(pipeline.map.grid.height * pipeline.map.grid.resolution, 0, 'f', 1)
                    .arg(pipeline.map.grid.resolution * 100, 0, 'f', 0)
              : QObject::tr("<br><b>No ground found</b>: nothing is traversable.");
  // What the loader could not work out changes how the whole result reads.
  if (!facts.caution.empty())
    text += QObject::tr("<br><b>Caution</b>: %1.")
                .arg(QString::fromStdString(facts.caution).toHtmlEscaped());
  // Without a recorded robot frame the heading drawn is one the box fits in, not one anybody
  // measured: the arrow would otherwise read as known.
  if (pipeline.trusted() && pipeline.map.robot_orientation >= 0 &&
      !pipeline.map.robot_heading_known)
    text += QObject::tr(
        "<br>Robot heading: guessed (no recorded robot pose); the reach starts "
        "from every heading its box fits in where it stands.");
  // A reach of a few cells beside a map of green says nothing by itself: say why it stops.
  if (pipeline.trusted() && !pipeline.map.reach_limit.empty())
    text += QObject::tr("<br>Reach: %1.")
                .arg(QString::fromStdString(pipeline.map.reach_limit).toHtmlEscaped());
  return text;
}

QString detailsOf(const SessionResult& result) {
  QString text = QString::fromStdString(toText(summarise(*result.scan)));
  text += QObject::tr("\nStage timings:\n");
  for (const StageTiming& stage : result.result->timings)
    text += QString("  %1  %2 ms\n")
                .arg(QString::fromStdString(stage.stage))
                .arg(stage.milliseconds, 0, 'f', 1);
  text += QObject::tr("  total  %1 ms").arg(result.result->total_ms, 0, 'f', 1);
  return text;
}

}  // namespace

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent), d_(std::make_unique<Private>()) {
  setObjectName("mainWindow");
  d_->session = new SegmentationSession(this);

  // Centre: the trust banner over the two views.
  auto* centre = new QWidget(this);
  auto* layout = new QVBoxLayout(centre);
  layout->setContentsMargins(0, 0, 0, 0);
  d_->trust_bar = new QWidget(centre);
  d_->trust_bar->setObjectName("trustBar");
  d_->trust_bar->setAttribute(Qt::WA_StyledBackground);
  auto* bar_layout = new QHBoxLayout(d_->trust_bar);
  bar_layout->setContentsMargins(0, 0, 8, 0);
  d_->banner = new QLabel(d_->trust_bar);
  d_->banner->setObjectName("trustBanner");
  d_->banner->setWordWrap(true);
  d_->banner->setStyleSheet("QLabel { color: white; padding: 8px; font-weight: bold; }");
  bar_layout->addWidget(d_->banner, 1);
  d_->confirm_up = new QPushButton(tr("Confirm up direction"), d_->trust_bar);
  d_->confirm_up->setObjectName("confirmUpButton");
  d_->pick_floor = new QPushButton(tr("Pick the floor in 3D..."), d_->trust_bar);
  d_->pick_floor->setObjectName("pickFloorButton");
  d_->type_pose = new QPushButton(tr("Type the pose..."), d_->trust_bar);
  d_->type_pose->setObjectName("typePoseButton");
  for (QPushButton* button : {d_->confirm_up, d_->pick_floor, d_->type_pose})
    bar_layout->addWidget(button);
  d_->trust_bar->hide();
  auto* views = new QSplitter(Qt::Horizontal, centre);
  views->setObjectName("viewSplitter");
  d_->scene = new SceneView(views);
  d_->map = new MapView(views);
  views->addWidget(d_->scene);
  views->addWidget(d_->map);
  views->setSizes({600, 600});
  layout->addWidget(d_->trust_bar);
  layout->addWidget(views, 1);
  setCentralWidget(centre);

  // Right: the robot on top, scan and scanner as tabs below.
  d_->robot = new RobotPanel(this);
  d_->scans = new ScanPanel(this);
  d_->hardware = new HardwarePanel(this);
  auto* robot_dock = dockFor(this, d_->robot, tr("Robot"), "robotDock");
  auto* scan_dock = dockFor(this, d_->scans, tr("Scan"), "scanDock");
  auto* hardware_dock = dockFor(this, d_->hardware, tr("Scanner"), "hardwareDock");
  addDockWidget(Qt::RightDockWidgetArea, robot_dock);
  addDockWidget(Qt::RightDockWidgetArea, scan_dock);
  addDockWidget(Qt::RightDockWidgetArea, hardware_dock);
  tabifyDockWidget(scan_dock, hardware_dock);
  scan_dock->raise();
  // The robot panel, the one worked most, is shown whole, however small the screen: at 1024 x 600
  // it showed four of its six rows (the maximum slope scrolled away) beside the recent scans.
  robot_dock->widget()->setMinimumHeight(d_->robot->minimumSizeHint().height());
  d_->docks = {robot_dock, scan_dock, hardware_dock};

  // Bottom: what is under the cursor, the shown scan's age, progress and cancel.
  d_->hover = new QLabel(this);
  d_->hover->setObjectName("hoverText");
  d_->age = new QLabel(this);
  d_->age->setObjectName("scanAge");
  d_->progress = new QProgressBar(this);
  d_->progress->setObjectName("progress");
  d_->progress->setMaximumWidth(160);
  d_->progress->hide();
  d_->cancel = new QPushButton(tr("Cancel"), this);
  d_->cancel->setObjectName("cancelButton");
  d_->cancel->hide();
  statusBar()->addWidget(d_->hover, 1);
  statusBar()->addPermanentWidget(d_->age);
  statusBar()->addPermanentWidget(d_->progress);
  statusBar()->addPermanentWidget(d_->cancel);

  buildMenus();
  addViewToolBar();
  // A click (not a drag) on the map stands the robot's box there in 3D.
  // With "Can it get there?" on, the click is the goal instead.
  connect(d_->map, &MapView::clicked, this, [this](double x, double y) {
    if (d_->goal_action->isChecked()) {
      d_->goal_action->setChecked(false);  // one click, one question
      canItGetThere(x, y);
      return;
    }
    d_->scene->showRobotAt(x, y, d_->map->yawAt(x, y));
  });
  connect(d_->map, &MapView::left, d_->hover, &QLabel::clear);
  connect(d_->map, &MapView::hovered, this, [this](double x, double y, const QString& description) {
    QString text = tr("x %1 m, y %2 m: %3").arg(x, 0, 'f', 2).arg(y, 0, 'f', 2).arg(description);
    if (d_->withheld) text += tr(" — up direction not confirmed: nothing shown as traversable");
    // The status bar's message hides the readout: the goal's answer, kept until the next goal,
    // was all the operator saw wherever the cursor went. It is carried on in the readout.
    if (d_->goal && !d_->goal_answer.isEmpty()) {
      text += tr("   |   %1").arg(d_->goal_answer);
      if (statusBar()->currentMessage() == d_->goal_answer) statusBar()->clearMessage();
    }
    d_->hover->setText(text);
  });
  // Written as the label in the view that measured it writes it (distanceInWords).
  const auto show_distance = [this](double metres, double uncertainty) {
    QString text = tr("Distance: %1").arg(distanceInWords(metres, uncertainty));
    if (uncertainty > 0.0)
      text += tr(" (± %1 m at this zoom: zoom in to measure finer)").arg(uncertainty, 0, 'f', 2);
    statusBar()->showMessage(text);
  };
  connect(d_->map, &MapView::measured, this, show_distance);
  connect(d_->scene, &SceneView::measured, this,
          [show_distance](double metres) { show_distance(metres, 0.0); });
  connect(d_->scene, &SceneView::pointPicked, this,
          [this](double x, double y, double z, const QString& what) {
            if (d_->floor_action->isChecked()) {
              d_->floor_action->setChecked(false);
              pickFloorAt(x, y, z);
              return;
            }
            d_->hover->setText(tr("Picked x %1 m, y %2 m, z %3 m: %4")
                                   .arg(x, 0, 'f', 2)
                                   .arg(y, 0, 'f', 2)
                                   .arg(z, 0, 'f', 2)
                                   .arg(what));
          });
  connect(d_->confirm_up, &QPushButton::clicked, this, &MainWindow::confirmEstimatedUp);
  connect(d_->pick_floor, &QPushButton::clicked, this,
          [this] { d_->floor_action->setChecked(true); });
  connect(d_->type_pose, &QPushButton::clicked, this, &MainWindow::editScanPose);
  connect(d_->robot, &RobotPanel::robotChanged, d_->session, &SegmentationSession::setRobot);
  connect(d_->robot, &RobotPanel::robotChanged, d_->hardware,
          [this](const RobotParams& robot) { d_->hardware->setRobotStep(robot.max_step); });
  connect(d_->robot, &RobotPanel::maxSlopeChanged, this, [this](double degrees) {
    SegmentationParams params = d_->session->params();
    params.ground.max_slope_deg = degrees;
    d_->session->setParams(params);
    // The ground is chosen again from the scan already loaded: no reload, the camera stays.
    d_->session->resegment();
  });
  connect(d_->scans, &ScanPanel::openRequested, this, &MainWindow::openScan);
  connect(d_->scans, &ScanPanel::browseRequested, this, &MainWindow::browseForScan);
  // Scan-and-stop: the views grey while a scan is acquired, the 3D view shows it growing, and the
  // saved acquisition is segmented and shown at once.
  connect(d_->hardware, &HardwarePanel::scanStarted, this, &MainWindow::markShownAsPrevious);
  connect(d_->hardware, &HardwarePanel::scanEndedUnsaved, this, [this] {
    d_->shown_is_previous = false;  // no newer scan came: the shown one is the latest again
    d_->map->setStale({});
    d_->scene->setStale({});
    updateAge();
  });
  connect(d_->hardware, &HardwarePanel::linesArrived, d_->scene, &SceneView::showArrivingScan);
  connect(d_->hardware, &HardwarePanel::scanSaved, this,
          [this](const QString& path) { openScan(path); });
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
  // The file that failed is where the operator stands in its folder: Next moves on from it.
  connect(d_->session, &SegmentationSession::openFailed, d_->scans, &ScanPanel::setFailed);
  connect(d_->session, &SegmentationSession::cancelled, this, &MainWindow::showCancelled);
  d_->age_timer.setInterval(kAgeRefreshMs);
  connect(&d_->age_timer, &QTimer::timeout, this, &MainWindow::updateAge);
  d_->age_timer.start();

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
  d_->robot->setEngineParams(params);
  params.robot = d_->robot->robot();
  d_->robot->setMaxSlopeDeg(params.ground.max_slope_deg);
  d_->session->setParams(params);
  updateTitle();
  restoreLayout();
  // Journals left by a crash of an earlier session wait in the scans folder.
  setUpJournalRecovery();
  QTimer::singleShot(0, this, [this] { checkUnfinishedJournals(); });
}

MainWindow::~MainWindow() = default;

void MainWindow::restoreLayout() {
  QSettings settings;
  if (!restoreGeometry(settings.value(kGeometryKey).toByteArray())) {
    const QScreen* screen = QGuiApplication::primaryScreen();
    const QSize available = screen ? screen->availableGeometry().size() : kDefaultSize;
    resize(std::min(kDefaultSize.width(), int(available.width() * kScreenShare)),
           std::min(kDefaultSize.height(), int(available.height() * kScreenShare)));
  }
  restoreState(settings.value(kStateKey).toByteArray());
}

void MainWindow::closeEvent(QCloseEvent* event) {
  QSettings settings;
  settings.setValue(kGeometryKey, saveGeometry());
  settings.setValue(kStateKey, saveState());
  QMainWindow::closeEvent(event);
}

void MainWindow::editParameters() {
  auto* dialog = new ParametersDialog(d_->session->params(), this);
  dialog->setAttribute(Qt::WA_DeleteOnClose);
  connect(dialog, &QDialog::accepted, this, [this, dialog] {
    const SegmentationParams params = dialog->params();
    QSettings().setValue(kParamsKey, QString::fromStdString(toJson(params).dump()));
    d_->robot->setEngineParams(params);
    d_->robot->setRobot(params.robot);
    d_->robot->setMaxSlopeDeg(params.ground.max_slope_deg);
    d_->session->setParams(params);
    // Stages 1-4 depend on the parameters too: segment the scan again (no reload).
    d_->session->resegment();
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

void MainWindow::openScan(const QString& path) {
  statusBar()->showMessage(tr("Loading %1 ...").arg(QFileInfo(path).fileName()));
  d_->session->openScan(path);
}

void MainWindow::setRobot(const RobotParams& robot) {
  d_->robot->setRobot(robot);
}

void MainWindow::nudgeRobotWidth(double metres) {
  RobotParams robot = d_->robot->robot();
  const auto [low, high] = d_->robot->limits("robot.width");
  robot.width = std::clamp(robot.width + metres, low, high);
  robot.name = "custom";
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

void MainWindow::markShownAsPrevious() {
  if (!d_->shown.result) return;
  d_->shown_is_previous = true;
  updateAge();
}

bool MainWindow::shownIsPrevious() const {
  return d_->shown_is_previous;
}

void MainWindow::updateAge() {
  if (!d_->shown.result || !d_->shown.scan_time.isValid()) {
    d_->age->clear();
    return;
  }
  const QString age = ageInWords(d_->shown.scan_time);
  // The Scan panel's summary says the age too: both move on together (they read 14 and 15 min).
  d_->scans->setSummary(humanSummary(d_->shown, d_->shown_facts));
  d_->age->setText(
      (d_->shown.scan_time_recorded ? tr("Scan taken %1, %2") : tr("Scan file saved %1, %2"))
          .arg(QLocale().toString(d_->shown.scan_time.time(), QLocale::ShortFormat))
          .arg(age));
  if (d_->shown_is_previous) {
    const QString note =
        tr("Previous scan, %1 — a new scan is being acquired; do not plan on this map.").arg(age);
    d_->map->setStale(note);
    d_->scene->setStale(note);
  }
}

void MainWindow::updateTitle() {
  if (!d_->shown.result) {
    setWindowTitle(tr("Clearway — no scan"));
    return;
  }
  const RobotParams& robot = d_->shown.result->robot;
  setWindowTitle(tr("%1 — robot %2 (%3 × %4 × %5 m) — Clearway")
                     .arg(QFileInfo(d_->shown.scan_path).fileName())
                     .arg(QString::fromStdString(robot.name))
                     .arg(robot.width, 0, 'f', 2)
                     .arg(robot.length, 0, 'f', 2)
                     .arg(robot.height, 0, 'f', 2));
}

void MainWindow::showResult(const SessionResult& result) {
  const PipelineResult& pipeline = *result.result;
  // A goal belongs to one scan in one frame: a robot change keeps it, a new scan or pose drops it.
  const bool new_scan = result.scan != d_->shown.scan;
  if (new_scan) dropGoal();
  // While a new scan is acquired the shown one stays the previous scan, whatever is run on it
  // again (a robot, a slope or a pose typed for it): a robot changed mid-acquisition brought the
  // old map back in full colour, "done", green under the growing cloud of the new one. Only the
  // new scan's file ends it.
  d_->shown_is_previous = d_->shown_is_previous && result.scan_path == d_->shown.scan_path;
  d_->shown = result;
  // An estimated up direction may be wrong: nothing is drawn traversable until it is confirmed.
  d_->withheld = pipeline.trusted() && pipeline.analysis->pose_source == PoseSource::kEstimated;
  if (d_->withheld) d_->shown.result = withholdTraversable(pipeline);
  if (!d_->shown_is_previous) d_->map->setStale({});
  d_->map->setResult(d_->shown.result);
  // An untrusted result still shows the cloud, but its scene has no ground and no boxes.
  d_->scene->setScene(d_->shown.scan, d_->shown.result);
  showPoseAndReach();
  // The safety rule: when the result cannot be trusted, say so and show nothing traversable.
  updateTrustBanner();
  d_->shown_facts = summarise(*result.scan);
  d_->scans->setCurrent(result.scan_path, humanSummary(result, d_->shown_facts), detailsOf(result));
  statusBar()->showMessage(tr("%1: done in %2 s")
                               .arg(QFileInfo(result.scan_path).fileName())
                               .arg(pipeline.total_ms / 1000.0, 0, 'f', 1),
                           5000);
  updateTitle();
  updateAge();
  if (d_->goal) planGoal();
  emit resultShown(pipeline.trusted());
}

void MainWindow::clearShown() {
  d_->shown = {};
  d_->shown_is_previous = false;
  d_->withheld = false;
  dropGoal();
  d_->map->clear();
  d_->scene->clearScene();
  d_->trust_bar->hide();
  findChild<QAction*>("confirmUpAction")->setEnabled(false);
  d_->scans->clearCurrent();
  updateTitle();
  updateAge();
}

void MainWindow::showFailure(const QString& reason) {
  // Nothing stays on screen that does not belong to the scan and robot named in the title: the
  // session dropped its result, so the views drop theirs.
  if (!d_->session->hasResult()) clearShown();
  statusBar()->showMessage(tr("Failed: %1").arg(reason));
  // Window-modal, not application-modal: nothing waits on it.
  auto* box = new QMessageBox(QMessageBox::Critical, tr("Clearway"), reason, QMessageBox::Ok, this);
  box->setObjectName("errorDialog");
  box->setAttribute(Qt::WA_DeleteOnClose);
  box->open();
  emit failureShown(reason);
}

void MainWindow::showCancelled() {
  // As a failure drops what is shown (showFailure), without its error dialog: the operator asked.
  if (!d_->session->hasResult()) clearShown();
  statusBar()->showMessage(d_->session->hasResult()
                               ? tr("Cancelled; the map shown is the one before.")
                               : tr("Cancelled; no scan is shown."));
  emit cancelShown();
}

QString MainWindow::exportTo(ExportKind kind, const QString& path,
                             const MapPictureOptions& picture) {
  const QString file = withExportExtension(path, kind);
  MapPictureOptions options = picture;
  options.palette = d_->palette;
  options.robot = d_->map->robotPose();
  options.path = d_->map->path();
  const QString problem =
      exportResult(kind, d_->shown, d_->session->params(), file, d_->scene, options);
  if (!problem.isEmpty()) {
    showFailure(problem);
    return problem;
  }
  statusBar()->showMessage(tr("Saved %1").arg(file), 10'000);
  emit exported(file);
  return {};
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
