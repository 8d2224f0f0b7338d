// Issue #11 in the console, under QT_QPA_PLATFORM=offscreen: the engine's robot pose and reachable
// cells are drawn and named (1), "Can it get there?" draws a path or gives the reason (2), the
// scan's pose source is shown and the operator can type the pose (3), and an estimated up
// direction shows nothing traversable until the operator confirms it or picks the floor (4).
// Scans come from core's simulator; a scan without pose has its sensor_pose reset.

#include <QAction>
#include <QComboBox>
#include <QFile>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QSettings>
#include <QSignalSpy>
#include <QStandardPaths>
#include <QStatusBar>
#include <QTemporaryDir>
#include <QtTest>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "clearway/io/scan_io.h"
#include "clearway/pose.h"
#include "clearway/sim/builtin_scenes.h"
#include "clearway/sim/rosi_simulator.h"
#include "clearway/ui/main_window.h"
#include "clearway/ui/map_view.h"
#include "clearway/ui/palette.h"
#include "clearway/ui/pose_dialog.h"
#include "clearway/ui/robot_panel.h"
#include "clearway/ui/segmentation_session.h"

using namespace clearway;
using clearway::ui::MainWindow;

namespace {

constexpr int kTimeoutMs = 60000;
// Lines of the simulated garage: as in core's reachability tests, where the 0.9 m door decides.
constexpr int kGarageLines = 423;
// The yard starts beyond the garage's 0.9 m door here (world x, as in core's reachability tests).
constexpr double kYardStartX = 4.6;
// A picked or typed up direction must come within this of the truth [deg].
constexpr double kUpToleranceDeg = 5.0;

const QRgb kTraversable =
    ui::cellColour(CellLabel::kTraversable, ui::PaletteKind::kColourBlindSafe).rgb();
int greenPixels(const QImage& image) {
  int count = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      count += image.pixel(x, y) == kTraversable;
  return count;
}

// Nothing in the map, on the 3D ground or among the obstacle cubes tells the robot to drive.
bool nothingDrivable(const PipelineResult& result) {
  const auto drivable = [](CellLabel label) {
    return label == CellLabel::kTraversable || label == CellLabel::kCareful ||
           label == CellLabel::kObstacle || label == CellLabel::kStairs;
  };
  for (const std::uint8_t label : result.map.labels)
    if (drivable(CellLabel(label))) return false;
  for (const CellLabel label : result.scene.vertex_labels)
    if (drivable(label)) return false;
  for (const SceneBox& box : result.scene.obstacles)
    if (drivable(box.label)) return false;
  return true;
}

struct Simulated {
  QString path;
  sim::ScannerPlacement placement;
  std::vector<PointClass> classes;
  Scan scan;
};

// The garage as the simulator sees it, saved with its pose (VIEWPOINT) or without.
Simulated simulateGarage(const QTemporaryDir& directory, bool with_pose) {
  const sim::Scene scene = *sim::builtinScene("garage");
  sim::SensorModel sensor;
  sensor.lines = kGarageLines;
  Simulated out;
  out.placement = sim::defaultPlacement(scene);
  auto simulated = sim::simulateRosi(scene, sensor, out.placement);
  if (!with_pose) simulated.scan.sensor_pose.reset();
  out.path = directory.filePath(with_pose ? "garage.pcd" : "garage_no_pose.pcd");
  saveRosiPcd(simulated.scan, out.path.toStdString());
  out.classes = simulated.truth.classes;
  out.scan = std::move(simulated.scan);
  return out;
}

// World up seen from the scanner: what a right pose gives.
Eigen::Vector3d trueUp(const Simulated& garage) {
  return garage.placement.worldFromScanner().linear().transpose() * Eigen::Vector3d::UnitZ();
}

double angleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

const PipelineResult& shown(const MainWindow& window) {
  return *window.shownResult().result;
}

// The centre of a yard cell (beyond the door, world x > kYardStartX) where the robot fits
// (green or orange) and whose reach is `reachable`; NaN when there is none.
Eigen::Vector2d yardCell(const MainWindow& window, const Simulated& garage, bool reachable) {
  const PipelineResult& result = shown(window);
  const TraversabilityMap& map = result.map;
  const Eigen::Isometry3d world_from_map =
      garage.placement.worldFromScanner() * result.analysis->map_from_scanner.inverse();
  for (int row = 0; row < map.grid.height; ++row)
    for (int column = 0; column < map.grid.width; ++column) {
      const Eigen::Vector2d centre = map.grid.centre(column, row);
      const CellLabel label = map.label(column, row);
      if ((world_from_map * Eigen::Vector3d(centre.x(), centre.y(), 0.0)).x() < kYardStartX ||
          (label != CellLabel::kTraversable && label != CellLabel::kCareful) ||
          bool(map.reach[map.grid.index(column, row)]) != reachable)
        continue;
      return centre;
    }
  return Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
}

// Opens a scan with a robot of `width` and waits until that robot's result is shown.
bool openWithRobot(MainWindow& window, const QString& path, double width) {
  RobotParams robot = window.robotPanel()->robot();
  robot.width = width;
  robot.name = "custom";
  window.setRobot(robot);
  window.openScan(path);
  const bool arrived = QTest::qWaitFor(
      [&] {
        return window.shownResult().result &&
               std::abs(window.shownResult().result->robot.width - width) < 1e-6 &&
               !window.session()->busy();
      },
      kTimeoutMs);
  // A robot re-run queued behind the load may still replace the result: let it land.
  QTest::qWait(3 * ui::SegmentationSession::kRobotDebounceMs);
  const bool settled = QTest::qWaitFor([&] { return !window.session()->busy(); }, kTimeoutMs);
  return arrived && settled && window.shownResult().result &&
         std::abs(window.shownResult().result->robot.width - width) < 1e-6;
}

QString scanInfo(const MainWindow& window) {
  return window.findChild<QLabel*>("scanInfo")->text();
}

}  // namespace

class PoseAndReachTest : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase() {
    QStandardPaths::setTestModeEnabled(true);
    QCoreApplication::setApplicationName("clearway-pose-test");
    QSettings().clear();
    QVERIFY(directory_.isValid());
    with_pose_ = simulateGarage(directory_, true);
    without_pose_ = simulateGarage(directory_, false);
  }

  void init() { QSettings().clear(); }

  // 1. The robot stands at the engine's pose in the map; the yard beyond the 0.9 m door fits a
  // 0.95 m robot but cannot be reached, and the readout says so.
  void theEnginesPoseAndReachAreDrawnAndNamed() {
    MainWindow window;
    window.show();
    window.mapView()->setRobotPose(9.0, 9.0, 1.0);  // anything but the engine's
    QVERIFY(openWithRobot(window, with_pose_.path, 0.95));
    const TraversabilityMap& map = shown(window).map;
    QVERIFY(shown(window).trusted());
    QCOMPARE(window.mapView()->robotPose().x, map.robot_pose.x);
    QCOMPARE(window.mapView()->robotPose().y, map.robot_pose.y);
    QCOMPARE(window.mapView()->robotPose().yaw, map.robot_pose.yaw);
    QCOMPARE(window.mapView()->reachable(), map.reach);
    QVERIFY(map.fits_not_reachable_cells > 0);
    const QString own = window.mapView()->describe(map.robot_pose.x, map.robot_pose.y);
    QVERIFY2(own.contains("reachable") && !own.contains("cannot"), qPrintable(own));
    const Eigen::Vector2d yard = yardCell(window, with_pose_, false);
    QVERIFY(!std::isnan(yard.x()));
    const QString beyond = window.mapView()->describe(yard.x(), yard.y());
    QVERIFY2(beyond.contains("fits, but cannot get there"), qPrintable(beyond));
    // The dimmed yard: the pane draws fewer pure-green cells than the map without reach.
    QVERIFY(greenPixels(window.mapView()->image()) <
            greenPixels(ui::mapImage(map, ui::PaletteKind::kColourBlindSafe)));
    // A failed open clears them with the result.
    window.openScan(directory_.filePath("missing.pcd"));
    QTRY_VERIFY_WITH_TIMEOUT(!window.mapView()->hasResult(), kTimeoutMs);
    QVERIFY(window.mapView()->reachable().empty());
  }

  // 1'. The scanner's mounting on the robot (Settings > Parameters) places the robot; a size
  // change on the robot panel keeps it.
  void theMountingSurvivesARobotSizeChange() {
    SegmentationParams params;
    params.robot.mount_x = 0.4;  // the scanner 0.4 m ahead of the robot's centre
    QSettings().setValue("segmentation/params", QString::fromStdString(toJson(params).dump()));
    MainWindow window;
    window.show();
    QVERIFY(openWithRobot(window, with_pose_.path, 0.9));
    QCOMPARE(shown(window).robot.mount_x, 0.4);
    QCOMPARE(window.mapView()->robotPose().x, shown(window).map.robot_pose.x);
    QSettings().clear();
  }

  // 2. "Can it get there?": G, then a click on the yard. 0.85 m: a path through the door, drawn;
  // 1.0 m: no, with a reason, and no path.
  void aGoalClickGivesAPathOrTheReason() {
    MainWindow window;
    window.resize(1400, 860);
    window.show();
    QVERIFY(QTest::qWaitForWindowExposed(&window));
    auto* goal = window.findChild<QAction*>("goalAction");
    QVERIFY(goal);
    QCOMPARE(goal->shortcut(), QKeySequence(Qt::Key_G));
    QVERIFY(openWithRobot(window, with_pose_.path, 0.85));
    window.mapView()->fit();
    goal->setChecked(true);
    const Eigen::Vector2d yard = yardCell(window, with_pose_, true);
    QVERIFY(!std::isnan(yard.x()));
    const QPoint click = window.mapView()->toWidget(yard.x(), yard.y()).toPoint();
    QVERIFY(window.mapView()->rect().contains(click));
    QTest::mouseClick(window.mapView(), Qt::LeftButton, {}, click);
    QVERIFY(!goal->isChecked());  // one click, one question
    const QString yes = window.statusBar()->currentMessage();
    QVERIFY2(yes.contains("Yes, reachable") && yes.contains(" m "), qPrintable(yes));
    qInfo("0.85 m robot: %s", qPrintable(yes));
    // The exported report carries the goal as `segment --goal` writes it.
    const QString report = directory_.filePath("goal-report.json");
    QVERIFY(window.exportTo(ui::ExportKind::kReportJson, report).isEmpty());
    QFile file(report);
    QVERIFY(file.open(QIODevice::ReadOnly));
    const QJsonObject goal_json =
        QJsonDocument::fromJson(file.readAll()).object()["goal"].toObject();
    QVERIFY(goal_json["reachable"].toBool());
    QVERIFY(goal_json["path"].toArray().size() >= 2);
    QVERIFY(goal_json["length_m"].toDouble() > 0.0);
    QVERIFY(window.mapView()->goal().has_value());  // the goal is marked where it was asked
    const auto& path = window.mapView()->path();
    QVERIFY(path.size() >= 2);
    QVERIFY(std::hypot(path.back().x - yard.x(), path.back().y - yard.y()) < 0.1);
    const RobotPose robot = shown(window).map.robot_pose;
    QVERIFY(std::hypot(path.front().x - robot.x, path.front().y - robot.y) < 0.1);

    // The wide robot: the same goal is re-planned for it when its result arrives.
    RobotParams wide = window.robotPanel()->robot();
    wide.width = 1.0;
    window.setRobot(wide);
    QTRY_VERIFY_WITH_TIMEOUT(std::abs(shown(window).robot.width - 1.0) < 1e-6, kTimeoutMs);
    const QString no = window.statusBar()->currentMessage();
    QVERIFY2(no.contains("Can it get there? No: ") && no.size() > 25, qPrintable(no));
    qInfo("1.0 m robot: %s", qPrintable(no));
    QVERIFY(window.mapView()->path().empty());
    // A "No" marks the goal too: the words alone did not say where it was.
    QVERIFY(window.mapView()->goal().has_value());
    QVERIFY(std::hypot(window.mapView()->goal()->x() - yard.x(),
                       window.mapView()->goal()->y() - yard.y()) < 0.1);
    // A goal nothing was seen at says so in words, not "(unknown)".
    const QString unseen = window.canItGetThere(shown(window).map.grid.origin.x() + 0.01,
                                                shown(window).map.grid.origin.y() + 0.01);
    QVERIFY2(unseen.contains("not seen well enough") && !unseen.contains("(unknown)"),
             qPrintable(unseen));
  }

  // 3. The pose source is named, and a typed pose (validated) segments the scan again.
  void thePoseSourceIsShownAndTheOperatorTypesIt() {
    MainWindow window;
    window.show();
    QSignalSpy shown_spy(&window, &MainWindow::resultShown);
    window.openScan(with_pose_.path);
    QVERIFY(shown_spy.wait(kTimeoutMs));
    QVERIFY2(scanInfo(window).contains("Pose: from the scan file"), qPrintable(scanInfo(window)));
    // A heading nobody recorded is said to be a guess; the arrow alone read as known.
    QCOMPARE(scanInfo(window).contains("Robot heading: guessed"),
             !shown(window).map.robot_heading_known);

    window.openScan(without_pose_.path);
    QVERIFY(shown_spy.wait(kTimeoutMs));
    QVERIFY2(scanInfo(window).contains("Pose: estimated from the scan (confidence"),
             qPrintable(scanInfo(window)));

    // A sidecar beside the scan (as acquisition writes it) wins over the file: the console
    // resolves the pose as the command line does.
    const QString sidecar_scan = directory_.filePath("garage_sidecar.pcd");
    QVERIFY(QFile::copy(without_pose_.path, sidecar_scan));
    SensorPose truth;
    const Eigen::Isometry3d world_from_scanner = without_pose_.placement.worldFromScanner();
    for (int r = 0; r < 3; ++r) {
      truth.position[std::size_t(r)] = world_from_scanner.translation()[r];
      for (int c = 0; c < 3; ++c)
        truth.rotation[std::size_t(3 * r + c)] = world_from_scanner.linear()(r, c);
    }
    writePoseSidecar(truth, "test", directory_.filePath("garage_sidecar.pose.json").toStdString());
    window.openScan(sidecar_scan);
    QVERIFY(shown_spy.wait(kTimeoutMs));
    QCOMPARE(shown(window).analysis->pose_source, PoseSource::kSidecar);
    QVERIFY2(scanInfo(window).contains(
                 "Pose: from the acquisition's pose file (sidecar) (garage_sidecar.pose.json)"),
             qPrintable(scanInfo(window)));
    QVERIFY(!window.withholdsTraversable());
    QVERIFY(shown(window).map.robot_heading_known);  // the sidecar's world is the robot's frame
    QVERIFY2(!scanInfo(window).contains("Robot heading: guessed"), qPrintable(scanInfo(window)));

    window.openScan(without_pose_.path);
    QVERIFY(shown_spy.wait(kTimeoutMs));
    window.editScanPose();
    auto* dialog = window.findChild<ui::PoseDialog*>("poseDialog");
    QVERIFY(dialog);
    auto* text = dialog->findChild<QLineEdit*>("poseText");
    auto* ok = dialog->findChild<QPushButton*>("poseOk");
    text->setText("0,0");  // core's parser refuses it, OK stays off
    QVERIFY(!ok->isEnabled());
    QVERIFY(!dialog->findChild<QLabel*>("poseProblem")->text().isEmpty());
    // A whole pose needs seven numbers; three are an up direction only.
    auto* kind = dialog->findChild<QComboBox*>("poseKind");
    kind->setCurrentIndex(1);
    text->setText("0,0,1");
    QVERIFY(!ok->isEnabled());
    text->setText("0,0,0.5,1,0,0,0");
    QVERIFY(ok->isEnabled());
    kind->setCurrentIndex(0);
    const Eigen::Vector3d up = trueUp(without_pose_);
    text->setText(
        QString("%1,%2,%3").arg(up.x(), 0, 'g', 9).arg(up.y(), 0, 'g', 9).arg(up.z(), 0, 'g', 9));
    QVERIFY(ok->isEnabled());
    ok->click();
    QVERIFY(shown_spy.wait(kTimeoutMs));
    const ScanAnalysis& analysis = *shown(window).analysis;
    QCOMPARE(analysis.pose_source, PoseSource::kCommandLine);
    QVERIFY(shown(window).trusted());
    QVERIFY(angleDeg(analysis.up, up) < 1e-3);
    QVERIFY2(scanInfo(window).contains("Pose: typed by the operator"),
             qPrintable(scanInfo(window)));
    QVERIFY(!window.withholdsTraversable());
    QVERIFY(greenPixels(window.mapView()->image()) > 1000);
  }

  // 4a. An estimated up direction draws nothing green until the operator confirms it.
  void anEstimatedUpShowsNothingGreenUntilConfirmed() {
    MainWindow window;
    window.show();
    QSignalSpy shown_spy(&window, &MainWindow::resultShown);
    window.openScan(without_pose_.path);
    QVERIFY(shown_spy.wait(kTimeoutMs));
    QCOMPARE(shown(window).analysis->pose_source, PoseSource::kEstimated);
    QVERIFY2(shown(window).trusted(), shown(window).reason.c_str());
    QVERIFY(window.withholdsTraversable());
    QCOMPARE(greenPixels(window.mapView()->image()), 0);
    QCOMPARE(shown(window).map.counts[std::size_t(CellLabel::kTraversable)], std::size_t(0));
    QVERIFY(nothingDrivable(shown(window)));
    auto* banner = window.findChild<QLabel*>("trustBanner");
    QVERIFY(banner->isVisible());
    qInfo("banner: %s", qPrintable(banner->text()));
    QVERIFY2(banner->text().contains("Up direction estimated from the scan (confidence"),
             qPrintable(banner->text()));
    auto* confirm = window.findChild<QPushButton*>("confirmUpButton");
    QVERIFY(confirm->isVisible());
    // A goal is refused while the estimate is unconfirmed.
    QVERIFY(window.canItGetThere(0.5, 0.0).contains("Confirm the up direction"));

    confirm->click();
    QVERIFY(shown_spy.wait(kTimeoutMs));
    QCOMPARE(shown(window).analysis->pose_source, PoseSource::kOperator);
    QVERIFY(shown(window).trusted());
    QVERIFY(!window.withholdsTraversable());
    QVERIFY(!banner->isVisible());
    QVERIFY(greenPixels(window.mapView()->image()) > 1000);
    QVERIFY(!nothingDrivable(shown(window)));
    qInfo("estimated up confirmed: %d green map pixels", greenPixels(window.mapView()->image()));
    QVERIFY2(scanInfo(window).contains("confirmed by the operator"), qPrintable(scanInfo(window)));
  }

  // 4a'. When the estimate is refused (no ground), the red banner offers the floor pick and a
  // typed pose, but nothing to confirm.
  void aRefusedEstimateOffersTheFloorAndAPose() {
    const sim::Scene scene = *sim::builtinScene("no-ground");
    sim::SensorModel sensor;
    sensor.lines = 100;
    auto simulated = sim::simulateRosi(scene, sensor, sim::defaultPlacement(scene));
    simulated.scan.sensor_pose.reset();
    const QString path = directory_.filePath("no_ground_no_pose.pcd");
    saveRosiPcd(simulated.scan, path.toStdString());
    MainWindow window;
    window.show();
    QSignalSpy shown_spy(&window, &MainWindow::resultShown);
    window.openScan(path);
    QVERIFY(shown_spy.wait(kTimeoutMs));
    QVERIFY(!shown(window).trusted());
    QVERIFY(!window.withholdsTraversable());
    QVERIFY(window.findChild<QLabel*>("trustBanner")->isVisible());
    QVERIFY(window.findChild<QPushButton*>("pickFloorButton")->isVisible());
    QVERIFY(window.findChild<QPushButton*>("typePoseButton")->isVisible());
    QVERIFY(!window.findChild<QPushButton*>("confirmUpButton")->isVisible());
    QCOMPARE(greenPixels(window.mapView()->image()), 0);
  }

  // 4b. "This is the floor": a point on the floor sets up from its plane (within 5 degrees of the
  // truth); a point where nothing was measured is refused with a reason.
  void pickingTheFloorSetsUp() {
    MainWindow window;
    window.show();
    QSignalSpy shown_spy(&window, &MainWindow::resultShown);
    window.openScan(without_pose_.path);
    QVERIFY(shown_spy.wait(kTimeoutMs));
    QVERIFY(window.findChild<QAction*>("floorAction"));

    const QString refused = window.pickFloorAt(100.0, 100.0, 100.0);
    QVERIFY2(refused.contains("no measured point"), qPrintable(refused));

    // A floor point of the truth, 1.5 to 3 m from the scanner, shown where the 3D view has it.
    const Scan& scan = without_pose_.scan;
    std::optional<Eigen::Vector3d> floor;
    for (std::size_t i = 0; i < scan.size() && !floor; ++i) {
      const Eigen::Vector3d p(scan.points[i].x, scan.points[i].y, scan.points[i].z);
      if (without_pose_.classes[i] == PointClass::kGround && scan.isValid(i) && p.norm() > 1.5 &&
          p.norm() < 3.0)
        floor = p;
    }
    QVERIFY(floor);
    const PipelineResult& before = shown(window);
    const Eigen::Vector3d in_view =
        before.trusted() ? Eigen::Vector3d(before.analysis->map_from_scanner * *floor) : *floor;
    QVERIFY(window.pickFloorAt(in_view.x(), in_view.y(), in_view.z()).isEmpty());
    QVERIFY(shown_spy.wait(kTimeoutMs));
    const ScanAnalysis& analysis = *shown(window).analysis;
    QCOMPARE(analysis.pose_source, PoseSource::kOperator);
    QVERIFY(shown(window).trusted());
    const double error = angleDeg(analysis.up, trueUp(without_pose_));
    QVERIFY2(error < kUpToleranceDeg, qPrintable(QString("up %1 deg off").arg(error)));
    qInfo("picked floor: up %.3f deg from the truth", error);
    QVERIFY(greenPixels(window.mapView()->image()) > 1000);
  }

 private:
  QTemporaryDir directory_;
  Simulated with_pose_;
  Simulated without_pose_;
};

QTEST_MAIN(PoseAndReachTest)
#include "pose_and_reach_test.moc"
