// The 3D view really renders (needs a display: run under xvfb-run, ctest label "render"): the
// garage shows green ground, red walls and orange edges and obstacles.

#include <QSignalSpy>
#include <QtTest>

#include "clearway/ui/main_window.h"
#include "clearway/ui/scene_view.h"

using clearway::ui::MainWindow;

namespace {

struct Colours {
  int green = 0, red = 0, orange = 0;
};

// Lighting shades the label colours; classify by hue, not by exact value.
Colours countColours(const QImage& image) {
  Colours c;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const QColor p(image.pixel(x, y));
      const int r = p.red(), g = p.green(), b = p.blue();
      if (g > r + 30 && g > b + 30)
        ++c.green;
      else if (r > g + 90 && r > b + 90)
        ++c.red;
      else if (r > 150 && g > 60 && g < r - 40 && b < 90)
        ++c.orange;
    }
  return c;
}

}  // namespace

class SceneViewRenderTest : public QObject {
  Q_OBJECT

 private slots:
  void theGarageShowsGroundWallsAndObstacles() {
    MainWindow window;
    window.resize(1400, 900);
    window.show();
    QVERIFY(QTest::qWaitForWindowExposed(&window));
    QVERIFY2(window.sceneView()->hasRenderer(), "no OpenGL renderer: run under xvfb-run");
    QSignalSpy shown(&window, &MainWindow::resultShown);
    window.openScan(CLEARWAY_SAMPLES_DIR "/garage.pcd");
    QVERIFY(shown.wait(30000));
    const QImage image = window.sceneView()->renderedImage();
    QVERIFY(!image.isNull());
    const Colours colours = countColours(image);
    image.save(QDir::temp().filePath("clearway_render_test.png"));
    QVERIFY2(colours.green > 500, qPrintable(QString("green %1").arg(colours.green)));
    QVERIFY2(colours.red > 500, qPrintable(QString("red %1").arg(colours.red)));
    QVERIFY2(colours.orange > 20, qPrintable(QString("orange %1").arg(colours.orange)));
  }
};

int main(int argc, char** argv) {
  clearway::ui::SceneView::prepareApplication();
  QApplication application(argc, argv);
  SceneViewRenderTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "scene_view_render_test.moc"
