#include "clearway/ui/map_drawing.h"

#include <QPainterPath>
#include <cmath>

namespace clearway::ui {
namespace {

// Grid lines are drawn only while they stay at least this many pixels apart.
constexpr double kMinGridSpacingPx = 8.0;
// Path footprints are drawn every this many metres along the path.
constexpr double kFootprintSpacing = 0.5;
const QColor kRobotColour(40, 120, 255);
// A distance measured this well [m] or better is written to the centimetre, else to 10 cm.
constexpr double kTwoDecimalsUncertainty = 0.005;

double niceLength(double metres) {
  const double power = std::pow(10.0, std::floor(std::log10(metres)));
  for (const double step : {1.0, 2.0, 5.0})
    if (step * power >= metres * 0.75) return step * power;
  return 10.0 * power;
}

QPolygonF footprint(const QTransform& map_to_picture, const PathPose& pose,
                    const RobotParams& robot) {
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  const double hl = robot.length / 2, hw = robot.width / 2;
  QPolygonF polygon;
  for (const auto& [a, b] : {std::pair{hl, hw}, {-hl, hw}, {-hl, -hw}, {hl, -hw}})
    polygon << map_to_picture.map(QPointF(pose.x + a * c - b * s, pose.y + a * s + b * c));
  return polygon;
}

}  // namespace

double roundStep(double extent, double parts) {
  if (!std::isfinite(extent) || !(parts >= 1.0)) return 1.0;
  for (double decade = 1.0;; decade *= 10.0)
    for (const double step : {decade, 2 * decade, 5 * decade})
      if (extent / step <= parts) return step;
}

QTransform mapToPicture(double pixels_per_metre, QPointF origin) {
  return QTransform(pixels_per_metre, 0, 0, -pixels_per_metre, origin.x(), origin.y());
}

void drawMetreGrid(QPainter& painter, const QTransform& map_to_picture, const QRectF& picture) {
  const double ppm = map_to_picture.m11();
  if (ppm < kMinGridSpacingPx) return;
  const QRectF area = map_to_picture.inverted().mapRect(picture);
  painter.save();
  painter.setPen(QPen(QColor(255, 255, 255, 50), 1));
  for (double x = std::ceil(area.left()); x <= area.right(); x += 1.0)
    painter.drawLine(map_to_picture.map(QPointF(x, area.top())),
                     map_to_picture.map(QPointF(x, area.bottom())));
  for (double y = std::ceil(area.top()); y <= area.bottom(); y += 1.0)
    painter.drawLine(map_to_picture.map(QPointF(area.left(), y)),
                     map_to_picture.map(QPointF(area.right(), y)));
  painter.restore();
}

void drawMapAxes(QPainter& painter, const QTransform& map_to_picture) {
  painter.save();
  const QPointF origin = map_to_picture.map(QPointF(0, 0));
  const std::pair<QPointF, QColor> axes[] = {{QPointF(1, 0), QColor(230, 60, 60)},
                                             {QPointF(0, 1), QColor(60, 200, 90)}};
  for (const auto& [tip, colour] : axes) {
    painter.setPen(QPen(colour, 2));
    const QPointF end = map_to_picture.map(tip);
    painter.drawLine(origin, end);
    painter.drawText(end + QPointF(4, -4), tip.x() > 0 ? "x" : "y");
  }
  painter.restore();
}

void drawRobot(QPainter& painter, const QTransform& map_to_picture, const PathPose& pose,
               const RobotParams& robot) {
  painter.save();
  painter.setRenderHint(QPainter::Antialiasing);
  painter.setPen(QPen(kRobotColour.lighter(150), 2));
  painter.setBrush(QColor(kRobotColour.red(), kRobotColour.green(), kRobotColour.blue(), 90));
  painter.drawPolygon(footprint(map_to_picture, pose, robot));
  // Heading: an arrow from the centre to a little beyond the front.
  const double reach = robot.length * 0.75;
  const QPointF centre = map_to_picture.map(QPointF(pose.x, pose.y));
  const QPointF tip = map_to_picture.map(
      QPointF(pose.x + reach * std::cos(pose.yaw), pose.y + reach * std::sin(pose.yaw)));
  painter.setPen(QPen(Qt::white, 2.5));
  painter.drawLine(centre, tip);
  const QLineF back(tip, centre);
  QLineF wing = back;
  wing.setLength(std::min(12.0, back.length() / 2));
  for (const double turn : {30.0, -30.0}) {
    QLineF w = wing;
    w.setAngle(back.angle() + turn);
    painter.drawLine(w);
  }
  painter.restore();
}

void drawPath(QPainter& painter, const QTransform& map_to_picture,
              const std::vector<PathPose>& path, const RobotParams& robot) {
  if (path.empty()) return;
  painter.save();
  painter.setRenderHint(QPainter::Antialiasing);
  QPolygonF line;
  for (const PathPose& pose : path)
    line << map_to_picture.map(QPointF(pose.x, pose.y));
  painter.setPen(QPen(QColor(90, 200, 255), 2, Qt::DashLine));
  painter.drawPolyline(line);
  painter.setPen(QPen(QColor(90, 200, 255), 1));
  painter.setBrush(Qt::NoBrush);
  double since = kFootprintSpacing;
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (i > 0) since += std::hypot(path[i].x - path[i - 1].x, path[i].y - path[i - 1].y);
    if (since < kFootprintSpacing && i + 1 < path.size()) continue;
    painter.drawPolygon(footprint(map_to_picture, path[i], robot));
    since = 0.0;
  }
  painter.restore();
}

QString distanceInWords(double metres, double uncertainty) {
  return QObject::tr("%1 m").arg(metres, 0, 'f', uncertainty <= kTwoDecimalsUncertainty ? 2 : 1);
}

void drawMeasurement(QPainter& painter, const QTransform& map_to_picture, QPointF from, QPointF to,
                     double uncertainty) {
  painter.save();
  painter.setRenderHint(QPainter::Antialiasing);
  const QPointF a = map_to_picture.map(from), b = map_to_picture.map(to);
  painter.setPen(QPen(Qt::white, 2));
  painter.drawLine(a, b);
  painter.setBrush(Qt::white);
  painter.drawEllipse(a, 3, 3);
  painter.drawEllipse(b, 3, 3);
  const double metres = std::hypot(to.x() - from.x(), to.y() - from.y());
  const QString text = distanceInWords(metres, uncertainty);
  const QPointF middle = (a + b) / 2 + QPointF(6, -6);
  QRectF box = painter.fontMetrics().boundingRect(text);
  box.moveBottomLeft(middle);
  painter.fillRect(box.adjusted(-3, -2, 3, 2), QColor(0, 0, 0, 180));
  painter.drawText(middle, text);
  painter.restore();
}

void drawGoal(QPainter& painter, QPointF at, bool reachable) {
  constexpr double kRadius = 9.0;
  painter.save();
  painter.setRenderHint(QPainter::Antialiasing);
  painter.setBrush(Qt::NoBrush);
  // A dark outline under the mark keeps it visible on every cell colour.
  for (const auto& [colour, width] :
       {std::pair{QColor(0, 0, 0, 200), 5.0},
        std::pair{reachable ? QColor(Qt::white) : QColor(255, 80, 80), 2.5}}) {
    painter.setPen(QPen(colour, width));
    if (reachable) {
      painter.drawEllipse(at, kRadius, kRadius);
    } else {
      painter.drawLine(at + QPointF(-kRadius, -kRadius), at + QPointF(kRadius, kRadius));
      painter.drawLine(at + QPointF(-kRadius, kRadius), at + QPointF(kRadius, -kRadius));
    }
  }
  painter.restore();
}

int drawLegend(QPainter& painter, QPoint top_left, PaletteKind palette) {
  const std::pair<CellLabel, QString> entries[] = {
      {CellLabel::kTraversable, QObject::tr("traversable")},
      {CellLabel::kCareful, QObject::tr("careful (narrow)")},
      {CellLabel::kObstacle, QObject::tr("low obstacle, sparse or unseen above")},
      {CellLabel::kImpassable, QObject::tr("impassable")},
      {CellLabel::kStairs, QObject::tr("stairs, with care")},
      {CellLabel::kUnknown, QObject::tr("not seen enough")}};
  constexpr int kSwatch = 14, kRow = 18;
  painter.save();
  const int rows = int(std::size(entries)) + 2;
  painter.fillRect(QRect(top_left - QPoint(4, 4), QSize(170, rows * kRow + 6)),
                   QColor(0, 0, 0, 160));
  int y = top_left.y();
  for (const auto& [label, name] : entries) {
    const QRect swatch(top_left.x(), y, kSwatch, kSwatch);
    painter.fillRect(swatch, cellColour(label, palette));
    if (label == CellLabel::kCareful || label == CellLabel::kObstacle) {
      painter.setPen(QPen(cellColour(label, palette).darker(200), 1.5));
      painter.setClipRect(swatch);
      for (int k = -kSwatch; k < kSwatch; k += 5) {
        painter.drawLine(swatch.left() + k, swatch.bottom(), swatch.left() + k + kSwatch,
                         swatch.top());
        if (label == CellLabel::kObstacle)
          painter.drawLine(swatch.left() + k, swatch.top(), swatch.left() + k + kSwatch,
                           swatch.bottom());
      }
      painter.setClipping(false);
    }
    painter.setPen(Qt::white);
    painter.drawText(QPoint(top_left.x() + kSwatch + 6, y + kSwatch - 2), name);
    y += kRow;
  }
  // Faded: the robot fits there but cannot get there from where it stands.
  const QRect faded(top_left.x(), y, kSwatch, kSwatch);
  painter.fillRect(faded, dimmedColour(cellColour(CellLabel::kTraversable, palette), palette));
  painter.fillRect(faded.adjusted(kSwatch / 2, 0, 0, 0),
                   dimmedColour(cellColour(CellLabel::kObstacle, palette), palette));
  painter.setPen(Qt::white);
  painter.drawText(QPoint(top_left.x() + kSwatch + 6, y + kSwatch - 2),
                   QObject::tr("faded: fits, out of reach"));
  y += kRow;
  painter.setPen(QPen(kRobotColour.lighter(150), 2));
  painter.drawRect(QRect(top_left.x(), y + 2, kSwatch, kSwatch - 4));
  painter.setPen(Qt::white);
  painter.drawText(QPoint(top_left.x() + kSwatch + 6, y + kSwatch - 2), QObject::tr("robot"));
  painter.restore();
  return rows * kRow;
}

void drawScaleBar(QPainter& painter, QPointF bottom_left, double pixels_per_metre,
                  double target_pixels) {
  const double metres = niceLength(target_pixels / pixels_per_metre);
  const double length = metres * pixels_per_metre;
  painter.save();
  painter.fillRect(QRectF(bottom_left + QPointF(-4, -22), QSizeF(length + 8, 26)),
                   QColor(0, 0, 0, 160));
  painter.setPen(QPen(Qt::white, 2));
  painter.drawLine(bottom_left, bottom_left + QPointF(length, 0));
  painter.drawLine(bottom_left, bottom_left + QPointF(0, -5));
  painter.drawLine(bottom_left + QPointF(length, 0), bottom_left + QPointF(length, -5));
  painter.drawText(bottom_left + QPointF(2, -8), metres >= 1
                                                     ? QObject::tr("%1 m").arg(metres)
                                                     : QObject::tr("%1 cm").arg(metres * 100));
  painter.restore();
}

void drawNorthArrow(QPainter& painter, QPointF centre) {
  painter.save();
  painter.setRenderHint(QPainter::Antialiasing);
  QPainterPath arrow;
  arrow.moveTo(centre + QPointF(0, -16));
  arrow.lineTo(centre + QPointF(8, 10));
  arrow.lineTo(centre + QPointF(0, 5));
  arrow.lineTo(centre + QPointF(-8, 10));
  arrow.closeSubpath();
  painter.fillPath(arrow, Qt::white);
  painter.setPen(Qt::white);
  painter.drawText(QRectF(centre.x() - 10, centre.y() - 34, 20, 16), Qt::AlignCenter, "N");
  painter.restore();
}

}  // namespace clearway::ui
