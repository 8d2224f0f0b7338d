#pragma once

// What the map pane and the exported map picture draw on top of the cells: metre grid, map axes,
// the robot with its heading, a planned path as footprints, a measured distance, the legend, a
// scale bar and a north arrow. Plain QPainter code, shared so the picture matches the pane.

#include <QPainter>
#include <QTransform>
#include <vector>

#include "clearway/segmentation/params.h"
#include "clearway/ui/palette.h"

namespace clearway::ui {

// A robot pose in the map frame: position [m] and heading [rad, from map +x towards +y].
struct PathPose {
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;
};

// map -> picture: x right, y up, `pixels_per_metre`, map (0, 0) at `origin` in the picture.
QTransform mapToPicture(double pixels_per_metre, QPointF origin);

void drawMetreGrid(QPainter& painter, const QTransform& map_to_picture, const QRectF& picture);
void drawMapAxes(QPainter& painter, const QTransform& map_to_picture);
void drawRobot(QPainter& painter, const QTransform& map_to_picture, const PathPose& pose,
               const RobotParams& robot);
void drawPath(QPainter& painter, const QTransform& map_to_picture,
              const std::vector<PathPose>& path, const RobotParams& robot);
// A measured distance in words, the one way the map's label, the 3D view's label and the status bar
// write it: "0.80 m", with two decimals only where the measurement is that good (`uncertainty` at
// most 5 mm; 0 for points given exactly), else one ("5.1 m"): at 3 cm a pixel a 0.80 m door
// measured 0.83 m, and read as wider than it is.
QString distanceInWords(double metres, double uncertainty);
// The line between two map positions with its length (distanceInWords) beside it.
void drawMeasurement(QPainter& painter, const QTransform& map_to_picture, QPointF from, QPointF to,
                     double uncertainty);
// Legend swatches with the same hatching as the cells; returns the height used.
int drawLegend(QPainter& painter, QPoint top_left, PaletteKind palette);
// The goal of "Can it get there?" at widget position `at`: a ring when reachable, a cross when not.
void drawGoal(QPainter& painter, QPointF at, bool reachable);
// The smallest round step (1, 2, 5 x 10^n, n >= 0) that cuts `extent` into at most `parts`.
double roundStep(double extent, double parts);
// A bar of a round length (1, 2, 5 x 10^n m) close to `target_pixels` long.
void drawScaleBar(QPainter& painter, QPointF bottom_left, double pixels_per_metre,
                  double target_pixels = 100.0);
// Map +y is drawn as north.
void drawNorthArrow(QPainter& painter, QPointF centre);

}  // namespace clearway::ui
