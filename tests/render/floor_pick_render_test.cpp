// "This is the floor" as the operator does it (issue #11): a scan without a pose is opened, its
// estimated up direction is withheld, the operator turns the tool on and clicks the floor in the
// 3D view; the plane there sets up (within 5 degrees of the simulator's truth) and the scan is
// segmented again with the operator's pose. Needs a display (label "render", xvfb-run).

#include <QAction>
#include <QApplication>
#include <QSettings>
#include <QSignalSpy>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QtTest>
#include <cmath>

#include "clearway/io/scan_io.h"
#include "clearway/sim/builtin_scenes.h"
#include "clearway/sim/rosi_simulator.h"
#include "clearway/ui/main_window.h"
#include "clearway/ui/scene_view.h"
#include "clearway/ui/segmentation_session.h"

using namespace clearway;
using clearway::ui::MainWindow;
using clearway::ui::SceneView;

namespace {

constexpr int kTimeoutMs = 60000;
constexpr double kUpToleranceDeg = 5.0;

}  // namespace

class FloorPickRenderTest : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase() {
    QStandardPaths::setTestModeEnabled(true);
    QCoreApplication::setApplicationName("clearway-floor-pick-test");
    QSettings().clear();
    QVERIFY(directory_.isValid());
  }

  void clickingTheFloorIn3dSetsUp() {
    const sim::Scene scene = *sim::builtinScene("garage");
    const sim::ScannerPlacement placement = sim::defaultPlacement(scene);
    auto simulated = sim::simulateRosi(scene, sim::SensorModel{}, placement);
    simulated.scan.sensor_pose.reset();  // acquired without a pose
    const QString path = directory_.filePath("garage_no_pose.pcd");
    saveRosiPcd(simulated.scan, path.toStdString());
    const Eigen::Vector3d true_up =
        placement.worldFromScanner().linear().transpose() * Eigen::Vector3d::UnitZ();

    MainWindow window;
    window.resize(1300, 800);
    window.show();
    QVERIFY(QTest::qWaitForWindowExposed(&window));
    QVERIFY(window.sceneView()->hasRenderer());
    QSignalSpy shown(&window, &MainWindow::resultShown);
    window.openScan(path);
    QVERIFY(shown.wait(kTimeoutMs));
    QVERIFY(window.withholdsTraversable());
    window.sceneView()->setCameraView(SceneView::CameraView::kTop);

    auto* floor = window.findChild<QAction*>("floorAction");
    QVERIFY(floor);
    floor->trigger();
    QVERIFY(floor->isChecked());
    // The garage floor, left of the middle of the top view (as in the measuring render test).
    SceneView* view = window.sceneView();
    QVERIFY(view->pickAt(QPoint(view->width() / 5, view->height() / 2)));
    QVERIFY(!floor->isChecked());  // one click
    QVERIFY(shown.wait(kTimeoutMs));
    const ScanAnalysis& analysis = *window.shownResult().result->analysis;
    QCOMPARE(analysis.pose_source, PoseSource::kOperator);
    QVERIFY(window.shownResult().result->trusted());
    QVERIFY(!window.withholdsTraversable());
    const double error = std::acos(std::clamp(analysis.up.dot(true_up), -1.0, 1.0)) * 180.0 / M_PI;
    QVERIFY2(error < kUpToleranceDeg, qPrintable(QString("up %1 deg off").arg(error)));
    qInfo("floor clicked in 3D: up %.3f deg from the truth", error);
  }

 private:
  QTemporaryDir directory_;
};

int main(int argc, char** argv) {
  SceneView::prepareApplication();
  QApplication application(argc, argv);
  FloorPickRenderTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "floor_pick_render_test.moc"
