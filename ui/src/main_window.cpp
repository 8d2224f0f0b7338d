#include "clearway/ui/main_window.h"

#include <QAction>
#include <QApplication>
#include <QDockWidget>
#include <QFileDialog>
#include <QFileInfo>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QProgressBar>
#include <QPushButton>
#include <QSplitter>
#include <QStatusBar>
#include <QVBoxLayout>
#include <cstdio>

#include "clearway/scan_summary.h"
#include "clearway/ui/map_view.h"
#include "clearway/ui/robot_panel.h"
#include "clearway/ui/scene_view.h"
#include "clearway/ui/segmentation_session.h"

namespace clearway::ui {

struct MainWindow::Private {
  SegmentationSession* session = nullptr;
  MapView* map = nullptr;
  SceneView* scene = nullptr;
  RobotPanel* robot = nullptr;
  QLabel* banner = nullptr;
  QLabel* scan_info = nullptr;
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
  d_->scan_info = new QLabel(tr("Open a scan (File > Open)."), this);
  d_->scan_info->setObjectName("scanInfo");
  d_->scan_info->setAlignment(Qt::AlignTop | Qt::AlignLeft);
  d_->scan_info->setTextInteractionFlags(Qt::TextSelectableByMouse);
  d_->scan_info->setMargin(6);
  auto* scan_dock = new QDockWidget(tr("Scan"), this);
  scan_dock->setObjectName("scanDock");
  scan_dock->setWidget(d_->scan_info);
  addDockWidget(Qt::RightDockWidgetArea, scan_dock);

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
  QAction* open = file->addAction(tr("&Open scan..."), this, [this] {
    const QString path = QFileDialog::getOpenFileName(
        this, tr("Open scan"), {},
        tr("Scans (*.pcd *.ply *.xyz *.txt *.dat *.asc *.bin *.3d);;All files (*)"));
    if (!path.isEmpty()) openScan(path);
  });
  open->setShortcut(QKeySequence::Open);
  file->addSeparator();
  file->addAction(tr("&Quit"), this, &QWidget::close)->setShortcut(QKeySequence::Quit);

  connect(d_->robot, &RobotPanel::robotChanged, d_->session, &SegmentationSession::setRobot);
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
  d_->session->setRobot(d_->robot->robot());
  resize(1200, 800);
}

MainWindow::~MainWindow() = default;

void MainWindow::openScan(const QString& path) {
  statusBar()->showMessage(tr("Loading %1 ...").arg(QFileInfo(path).fileName()));
  d_->session->openScan(path);
}

void MainWindow::setRobot(const RobotParams& robot) {
  d_->robot->setRobot(robot);
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
  d_->map->setResult(result.result);
  // An untrusted result still shows the cloud, but its scene has no ground and no boxes.
  d_->scene->setScene(result.scan, result.result);
  // The safety rule: when the result cannot be trusted, say so and show nothing traversable.
  d_->banner->setVisible(!pipeline.trusted());
  d_->banner->setText(tr("Nothing is shown as traversable: %1")
                          .arg(QString::fromStdString(pipeline.analysis.reason)));
  d_->scan_info->setText(QString::fromStdString(toText(summarise(*result.scan))));
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
