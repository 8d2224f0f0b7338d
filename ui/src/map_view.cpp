#include "clearway/ui/map_view.h"

#include <QMouseEvent>
#include <QPainter>
#include <QWheelEvent>
#include <cmath>
#include <limits>

#include "clearway/scene/scene_geometry.h"

namespace clearway::ui {

QImage mapImage(const TraversabilityMap& map) {
  QImage image(std::max(map.grid.width, 1), std::max(map.grid.height, 1), QImage::Format_RGB32);
  image.fill(QColor(60, 60, 60));
  for (int row = 0; row < map.grid.height; ++row)
    for (int column = 0; column < map.grid.width; ++column) {
      const auto rgb = labelColour(map.label(column, row));
      image.setPixel(column, map.grid.height - 1 - row, qRgb(rgb[0], rgb[1], rgb[2]));
    }
  return image;
}

MapView::MapView(QWidget* parent) : QWidget(parent) {
  setObjectName("mapView");
  setMouseTracking(true);
  setMinimumSize(320, 240);
  setAutoFillBackground(true);
  QPalette palette = this->palette();
  palette.setColor(QPalette::Window, QColor(40, 40, 40));
  setPalette(palette);
}

void MapView::setResult(std::shared_ptr<const PipelineResult> result) {
  const bool same_grid = result_ && result && result_->map.grid.origin == result->map.grid.origin &&
                         result_->map.grid.width == result->map.grid.width;
  result_ = std::move(result);
  image_ = result_ ? mapImage(result_->map) : QImage();
  if (!same_grid) fitted_ = false;  // a new scan: show all of it; a new robot: keep the view
  if (!fitted_) fitToView();
  update();
}

void MapView::clear() {
  setResult(nullptr);
}

void MapView::fitToView() {
  if (!result_ || image_.isNull()) return;
  const MapGrid& grid = result_->map.grid;
  const double width_m = grid.width * grid.resolution, height_m = grid.height * grid.resolution;
  pixels_per_metre_ = std::max(1.0, 0.95 * std::min(width() / width_m, height() / height_m));
  // Centre the map: map x grows right, map y grows up.
  const QPointF map_centre(grid.origin.x() + width_m / 2, grid.origin.y() + height_m / 2);
  offset_ = QPointF(width() / 2.0 - map_centre.x() * pixels_per_metre_,
                    height() / 2.0 + map_centre.y() * pixels_per_metre_);
  fitted_ = true;
}

QPointF MapView::toMap(const QPointF& widget) const {
  return {(widget.x() - offset_.x()) / pixels_per_metre_,
          (offset_.y() - widget.y()) / pixels_per_metre_};
}

QPointF MapView::toWidget(double map_x, double map_y) const {
  return {offset_.x() + map_x * pixels_per_metre_, offset_.y() - map_y * pixels_per_metre_};
}

QString MapView::describe(double map_x, double map_y) const {
  if (!result_) return {};
  const TraversabilityMap& map = result_->map;
  const Eigen::Vector2i cell = map.grid.cellOf(map_x, map_y);
  if (!map.grid.inside(cell.x(), cell.y())) return tr("outside the map");
  const CellLabel label = map.label(cell.x(), cell.y());
  QString text = QString::fromUtf8(labelName(label).data(), int(labelName(label).size()));
  const auto reason = reasonName(CellReason(map.reasons[map.grid.index(cell.x(), cell.y())]));
  if (!reason.empty()) text += ": " + QString::fromUtf8(reason.data(), int(reason.size()));
  // On a staircase: its steps, rise, tread and direction, and whether this robot climbs it.
  const auto& stairs = result_->analysis.stairs;
  if (const int flight = stairs.staircaseAt(map.grid.index(cell.x(), cell.y())); flight >= 0)
    text += " (" +
            QString::fromStdString(
                describeStaircase(stairs.staircases[std::size_t(flight)], result_->robot)) +
            ")";
  return text;
}

double MapView::yawAt(double map_x, double map_y) const {
  if (!result_) return std::numeric_limits<double>::quiet_NaN();
  const Eigen::Vector2i cell = result_->map.grid.cellOf(map_x, map_y);
  if (!result_->map.grid.inside(cell.x(), cell.y()))
    return std::numeric_limits<double>::quiet_NaN();
  return result_->map.yawDegrees(cell.x(), cell.y());
}

void MapView::paintEvent(QPaintEvent*) {
  QPainter painter(this);
  if (!result_ || image_.isNull()) {
    painter.setPen(Qt::lightGray);
    painter.drawText(rect(), Qt::AlignCenter, tr("No traversability map yet"));
    return;
  }
  const MapGrid& grid = result_->map.grid;
  const QPointF top_left =
      toWidget(grid.origin.x(), grid.origin.y() + grid.height * grid.resolution);
  const QSizeF size(grid.width * grid.resolution * pixels_per_metre_,
                    grid.height * grid.resolution * pixels_per_metre_);
  painter.drawImage(QRectF(top_left, size), image_);

  // The robot's footprint at the cursor, in an orientation that fits there.
  if (cursor_inside_) {
    const Eigen::Vector2i cell = grid.cellOf(cursor_map_.x(), cursor_map_.y());
    if (grid.inside(cell.x(), cell.y())) {
      const double yaw = result_->map.yawDegrees(cell.x(), cell.y());
      painter.save();
      painter.translate(toWidget(cursor_map_.x(), cursor_map_.y()));
      painter.rotate(-(std::isnan(yaw) ? 0.0 : yaw));
      painter.setPen(QPen(std::isnan(yaw) ? Qt::red : Qt::white, 1.5));
      painter.setBrush(Qt::NoBrush);
      const double length = result_->robot.length * pixels_per_metre_,
                   width = result_->robot.width * pixels_per_metre_;
      painter.drawRect(QRectF(-length / 2, -width / 2, length, width));
      painter.restore();
    }
  }

  // Scale bar: one metre, bottom left.
  painter.setPen(QPen(Qt::white, 2));
  const QPointF start(12, height() - 14);
  painter.drawLine(start, start + QPointF(pixels_per_metre_, 0));
  painter.drawText(start + QPointF(0, -6), tr("1 m"));

  // Legend, top left.
  const std::pair<CellLabel, QString> entries[] = {
      {CellLabel::kTraversable, tr("traversable")},  {CellLabel::kCareful, tr("careful")},
      {CellLabel::kObstacle, tr("obstacle")},        {CellLabel::kImpassable, tr("impassable")},
      {CellLabel::kStairs, tr("stairs, with care")}, {CellLabel::kUnknown, tr("unobserved")}};
  int y = 10;
  for (const auto& [label, name] : entries) {
    const auto rgb = labelColour(label);
    painter.fillRect(QRect(10, y, 12, 12), QColor(rgb[0], rgb[1], rgb[2]));
    painter.setPen(Qt::white);
    painter.drawText(QPoint(28, y + 11), name);
    y += 16;
  }
}

void MapView::wheelEvent(QWheelEvent* event) {
  const QPointF anchor = event->position();
  const QPointF before = toMap(anchor);
  pixels_per_metre_ =
      std::clamp(pixels_per_metre_ * std::pow(1.0015, event->angleDelta().y()), 2.0, 2000.0);
  const QPointF after = toWidget(before.x(), before.y());
  offset_ += anchor - after;  // keep the point under the cursor in place
  update();
}

void MapView::mousePressEvent(QMouseEvent* event) {
  dragging_ = true;
  last_drag_ = event->pos();
  const QPointF map = toMap(event->pos());
  emit clicked(map.x(), map.y());
}

void MapView::mouseMoveEvent(QMouseEvent* event) {
  if (dragging_) {
    offset_ += event->pos() - last_drag_;
    last_drag_ = event->pos();
  }
  cursor_map_ = toMap(event->pos());
  cursor_inside_ = true;
  emit hovered(cursor_map_.x(), cursor_map_.y(), describe(cursor_map_.x(), cursor_map_.y()));
  update();
}

void MapView::mouseReleaseEvent(QMouseEvent*) {
  dragging_ = false;
}

void MapView::resizeEvent(QResizeEvent*) {
  if (result_) fitToView();
}

}  // namespace clearway::ui
