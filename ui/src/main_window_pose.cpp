// The main window's pose and reach (issue #11): the robot's pose and reachable cells in both
// views, "Can it get there?", the scan's pose source in the trust banner, the operator's pose
// (typed, a confirmed estimate, a picked floor), and the rule that an estimated up direction
// shows nothing traversable until the operator confirms it.

#include <QAction>
#include <QPushButton>
#include <QStatusBar>
#include <cmath>

#include "clearway/traversability/reachability.h"
#include "clearway/ui/floor_pick.h"
#include "clearway/ui/main_window.h"
#include "clearway/ui/map_view.h"
#include "clearway/ui/pose_dialog.h"
#include "clearway/ui/scene_view.h"
#include "main_window_private.h"

namespace clearway::ui {
namespace {

constexpr double kDegrees = 180.0 / M_PI;

const char* const kEstimatedStyle = "QWidget#trustBar { background: #8d4a00; }";
const char* const kUntrustedStyle = "QWidget#trustBar { background: #b71c1c; }";

// The banner of a result on which nothing is green: the reason, after "Nothing is shown as
// traversable" unless it says so itself ("scan too sparse to show anything traversable: ...",
// "nothing traversable: ..."), where the prefix only repeated it.
QString nothingGreenBanner(const std::string& reason) {
  QString text = QString::fromStdString(reason);
  if (!text.contains(QStringLiteral("traversable")))
    return QObject::tr("Nothing is shown as traversable: %1").arg(text);
  if (!text.isEmpty()) text[0] = text[0].toUpper();
  return text;
}

// A partial scan's line in the banner: that it is partial, why when its record says, and what
// that means for the map.
QString partialScanBanner(const SessionResult& shown) {
  const QString why =
      shown.partial_reason.isEmpty()
          ? QObject::tr("the acquisition ended before the turn was complete")
          : QObject::tr("the acquisition ended early (%1)").arg(shown.partial_reason);
  return QObject::tr(
             "Partial scan: %1. What the rest of the turn would have seen is unknown, not free: "
             "scan again before planning there.")
      .arg(why);
}

}  // namespace

std::shared_ptr<const PipelineResult> withholdTraversable(const PipelineResult& result) {
  auto withheld = std::make_shared<PipelineResult>(result);
  TraversabilityMap& map = withheld->map;
  map.counts = {};
  for (std::uint8_t& label : map.labels) {
    if (drivable(CellLabel(label))) label = std::uint8_t(CellLabel::kUnknown);
    ++map.counts[label];
  }
  map.reach.clear();
  map.reachable_cells = 0;
  map.fits_not_reachable_cells = 0;
  map.reach_limit.clear();
  for (CellLabel& label : withheld->scene.vertex_labels)
    if (drivable(label)) label = CellLabel::kUnknown;
  for (SceneBox& box : withheld->scene.obstacles)  // orange "probably passable" cubes
    if (drivable(box.label)) box.label = CellLabel::kUnknown;
  withheld->goal.reset();
  return withheld;
}

void MainWindow::showPoseAndReach() {
  const PipelineResult& result = *d_->shown.result;
  // Without ground there is no map frame: the robot back at the scanner's foot, no reach.
  const RobotPose pose = result.trusted() ? result.map.robot_pose : RobotPose{};
  d_->map->setRobotPose(pose.x, pose.y, pose.yaw);
  d_->scene->setRobotPose(pose.x, pose.y, pose.yaw);
  d_->map->setReachable(result.map.reach);
  d_->scene->setReachable(result.map.reach);
}

void MainWindow::updateTrustBanner() {
  const PipelineResult& result = *d_->shown.result;
  const ScanAnalysis& analysis = *result.analysis;
  // The operator's ways out when the scan's own pose is missing: confirm, pick, type.
  const bool no_pose =
      analysis.pose_source == PoseSource::kEstimated || analysis.pose_source == PoseSource::kNone;
  QStringList warnings;
  if (d_->withheld) {
    warnings << tr("Up direction estimated from the scan (confidence %1): confirm it or pick the "
                   "floor. Nothing is shown as traversable until then.")
                    .arg(analysis.up_confidence, 0, 'f', 2);
  } else if (!result.trusted() || !result.reason.empty()) {
    // Untrusted: red. Trusted ground on which nothing is green (too sparse, or the robot fits
    // nowhere): amber, with the map's reason.
    warnings << nothingGreenBanner(result.reason);
  }
  // Whatever else is said: part of the turn is missing, and its map would read as the whole place.
  if (d_->shown.partial) warnings << partialScanBanner(d_->shown);
  d_->banner->setText(warnings.join('\n'));
  d_->trust_bar->setStyleSheet(result.trusted() ? kEstimatedStyle : kUntrustedStyle);
  d_->confirm_up->setVisible(d_->withheld);
  d_->pick_floor->setVisible(no_pose);
  d_->type_pose->setVisible(no_pose || !result.trusted());
  const bool show = !warnings.isEmpty();
  d_->banner->setVisible(show);
  d_->trust_bar->setVisible(show);
  findChild<QAction*>("confirmUpAction")->setEnabled(d_->withheld);
}

bool MainWindow::withholdsTraversable() const {
  return d_->withheld;
}

const SessionResult& MainWindow::shownResult() const {
  return d_->shown;
}

void MainWindow::editScanPose() {
  if (!d_->shown.scan) {
    statusBar()->showMessage(tr("Open a scan first: the pose belongs to a scan."));
    return;
  }
  auto* dialog = new PoseDialog(this);
  dialog->setAttribute(Qt::WA_DeleteOnClose);
  connect(dialog, &QDialog::accepted, this,
          [this, dialog] { setScanPose(dialog->request(), PoseSource::kCommandLine); });
  dialog->open();
}

void MainWindow::setScanPose(const PoseRequest& request, PoseSource source) {
  if (!d_->shown.scan) return;
  statusBar()->showMessage(tr("Segmenting with the pose %1 ...").arg(poseSourceInWords(source)));
  d_->session->setScanPose(request, source);
}

void MainWindow::confirmEstimatedUp() {
  if (!d_->withheld) return;
  PoseRequest request;
  request.up = d_->shown.result->analysis->up;
  setScanPose(request, PoseSource::kOperator);
}

QString MainWindow::pickFloorAt(double x, double y, double z) {
  if (!d_->shown.scan || !d_->shown.result) return tr("Open a scan first.");
  const PipelineResult& result = *d_->shown.result;
  // The 3D view draws in the map frame when there is ground, in the scanner frame otherwise.
  const Eigen::Isometry3d view_from_scanner =
      result.trusted() ? result.analysis->map_from_scanner : Eigen::Isometry3d::Identity();
  const Eigen::Vector3d scanner_point = view_from_scanner.inverse() * Eigen::Vector3d(x, y, z);
  const FloorPick pick = floorUpAt(*d_->shown.scan, *result.analysis, scanner_point);
  if (!pick.up) {
    const QString why = tr("Not the floor: %1").arg(QString::fromStdString(pick.reason));
    statusBar()->showMessage(why);
    return why;
  }
  PoseRequest request;
  request.up = *pick.up;
  setScanPose(request, PoseSource::kOperator);
  statusBar()->showMessage(tr("The floor: %1; segmenting with its up direction ...")
                               .arg(QString::fromStdString(pick.how)));
  return {};
}

QString MainWindow::canItGetThere(double map_x, double map_y) {
  d_->goal = QPointF(map_x, map_y);
  planGoal();
  return statusBar()->currentMessage();
}

void MainWindow::planGoal() {
  std::vector<PathPose> path;
  QString answer;
  bool reachable = false;
  const PipelineResult* result = d_->shown.result.get();
  if (!result) {
    answer = tr("Can it get there? Open a scan first.");
  } else if (!result->trusted()) {
    answer = tr("Can it get there? No: no ground was found in this scan.");
  } else if (d_->withheld) {
    answer = tr("Can it get there? Confirm the up direction or pick the floor first.");
  } else if (d_->shown_is_previous) {
    // The map under the question is the previous scan's: planning on it is what its grey says
    // not to do.
    answer =
        tr("Can it get there? Not on this map: a new scan is being acquired; ask again "
           "once it is shown.");
  } else {
    const GoalResult goal = planPath(result->map, d_->goal->x(), d_->goal->y());
    // The exported report carries the question and its answer, as `segment --goal` writes it.
    auto with_goal = std::make_shared<PipelineResult>(*result);
    with_goal->goal = goal;
    d_->shown.result = std::move(with_goal);
    for (const clearway::PathPose& pose : goal.path)
      path.push_back({pose.x, pose.y, pose.heading_deg / kDegrees});
    reachable = goal.reachable;
    answer = goal.reachable
                 ? tr("Can it get there? Yes, reachable: a path of %1 m from where it stands.")
                       .arg(goal.length_m, 0, 'f', 1)
                 : tr("Can it get there? No: %1").arg(QString::fromStdString(goal.reason));
    if (goal.reachable && goal.unvouched_m > 0.0)
      answer += tr(" %1 m of it over ground not vouched for (sparse, or unseen up to its height): "
                   "drive with care.")
                    .arg(goal.unvouched_m, 0, 'f', 1);
  }
  d_->map->setPath(path);
  d_->map->setGoal(result ? d_->goal : std::nullopt, reachable);
  d_->scene->setPath(path);
  d_->goal_answer = answer;
  statusBar()->showMessage(answer);
}

void MainWindow::dropGoal() {
  d_->goal.reset();
  d_->goal_answer.clear();
  d_->map->setPath({});
  d_->map->setGoal(std::nullopt, false);
  d_->scene->setPath({});
}

}  // namespace clearway::ui
