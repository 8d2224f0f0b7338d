#include "clearway/ui/map_view.h"

#include <QMouseEvent>
#include <QPainter>
#include <QWheelEvent>
#include <cmath>
#include <limits>

namespace clearway::ui {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// The passage readout looks this far each way [m] in this many directions over 180 degrees.
constexpr double kPassageSearch = 4.0;
constexpr int kPassageDirections = 16;
// A press that moves less than this [px] before release is a click, not a drag.
constexpr int kClickSlopPx = 4;
// "Fit map" shows at least this many metres each way (a few robot lengths).
constexpr double kSmallestFitExtent = 4.0;

// What bounds a passage: unobserved cells and red cells with something in the way. Red cells that
// are only "too narrow" for the robot's centre are free space inside the passage.
bool blocksPassage(const TraversabilityMap& map, int column, int row) {
  const CellLabel label = map.label(column, row);
  if (label == CellLabel::kUnknown) return true;
  return label == CellLabel::kImpassable &&
         CellReason(map.reasons[map.grid.index(column, row)]) != CellReason::kTooNarrow;
}

}  // namespace

MapView::MapView(QWidget* parent) : QWidget(parent) {
  setObjectName("mapView");
  setMouseTracking(true);
  setMinimumSize(240, 180);
  setAutoFillBackground(true);
  QPalette palette = this->palette();
  palette.setColor(QPalette::Window, QColor(40, 40, 40));
  setPalette(palette);
}

void MapView::setResult(std::shared_ptr<const PipelineResult> result) {
  const bool same_grid = result_ && result && result_->map.grid.origin == result->map.grid.origin &&
                         result_->map.grid.width == result->map.grid.width &&
                         result_->map.grid.height == result->map.grid.height;
  result_ = std::move(result);
  if (!same_grid) {
    // A new scan: show all of it; its path and reach are not the old scan's.
    fitted_ = false;
    path_.clear();
    goal_.reset();
    reachable_.clear();
    measure_points_.clear();
    // The cursor's footprint stood where the old map's point under it now lies, away from the
    // cursor: it comes back with the next move.
    cursor_inside_ = false;
  }
  rebuildImage();
  if (!fitted_) fit();
  update();
}

void MapView::clear() {
  setResult(nullptr);
  stale_note_.clear();
  cursor_inside_ = false;
  update();
}

void MapView::rebuildImage() {
  image_ = result_ ? mapImage(result_->map, palette_, reachable_) : QImage();
}

void MapView::setRobotPose(double x, double y, double yaw) {
  robot_pose_ = {x, y, yaw};
  update();
}

void MapView::setPath(std::vector<PathPose> path) {
  path_ = std::move(path);
  update();
}

void MapView::setGoal(std::optional<QPointF> goal, bool reachable) {
  goal_ = goal;
  goal_reachable_ = reachable;
  update();
}

void MapView::setReachable(std::vector<std::uint8_t> reachable) {
  reachable_ = std::move(reachable);
  rebuildImage();
  update();
}

void MapView::setPaletteKind(PaletteKind palette) {
  palette_ = palette;
  rebuildImage();
  update();
}

void MapView::setStale(const QString& note) {
  stale_note_ = note;
  update();
}

void MapView::setMeasuring(bool on) {
  measuring_ = on;
  measure_points_.clear();
  setCursor(on ? Qt::CrossCursor : Qt::ArrowCursor);
  update();
}

void MapView::measureBetween(const QPointF& from, const QPointF& to) {
  measure_points_ = {from, to};
  measure_uncertainty_ = 0.0;
  emit measured(std::hypot(to.x() - from.x(), to.y() - from.y()), measure_uncertainty_);
  update();
}

void MapView::fit() {
  if (!result_ || image_.isNull() || width() <= 0 || height() <= 0) return;
  const MapGrid& grid = result_->map.grid;
  const double width_m = grid.width * grid.resolution, height_m = grid.height * grid.resolution;
  // A map of a few cells (no ground: one unknown cell) is shown at a scale a robot fits in, not
  // blown up to centimetres.
  pixels_per_metre_ =
      std::max(1.0, 0.95 * std::min(width() / std::max(width_m, kSmallestFitExtent),
                                    height() / std::max(height_m, kSmallestFitExtent)));
  // Centre the map: map x grows right, map y grows up.
  const QPointF map_centre(grid.origin.x() + width_m / 2, grid.origin.y() + height_m / 2);
  offset_ = QPointF(width() / 2.0 - map_centre.x() * pixels_per_metre_,
                    height() / 2.0 + map_centre.y() * pixels_per_metre_);
  fitted_ = true;
  update();
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
  // Where it fits, whether it can get there from where it stands.
  const bool free = label == CellLabel::kTraversable || label == CellLabel::kCareful;
  if (free && reachable_.size() == map.labels.size())
    text += reachable_[map.grid.index(cell.x(), cell.y())] ? tr(", reachable")
                                                           : tr(", fits, but cannot get there");
  // On a staircase: its steps, rise, tread and direction, and whether this robot climbs it.
  const auto& stairs = result_->analysis->stairs;
  if (const int flight = stairs.staircaseAt(map.grid.index(cell.x(), cell.y())); flight >= 0)
    text += " (" +
            QString::fromStdString(
                describeStaircase(stairs.staircases[std::size_t(flight)], result_->robot)) +
            ")";
  const double passage = passageWidthAt(map_x, map_y);
  // A passage as wide as the robot does not say why its box fits nowhere ("too narrow — passage
  // 1.80 m wide" for a 0.85 m robot): the box meets a corner, unseen ground or a wall end in every
  // heading there, which the width across one direction does not see.
  const bool passage_explains =
      !(label == CellLabel::kImpassable &&
        CellReason(map.reasons[map.grid.index(cell.x(), cell.y())]) == CellReason::kTooNarrow &&
        passage >= result_->robot.width);
  if (!std::isnan(passage) && passage_explains)
    text += tr(" — passage %1 m wide").arg(passage, 0, 'f', 2);
  else if (!std::isnan(passage))
    text += tr(" — its box meets something in every heading here");
  return text;
}

double MapView::yawAt(double map_x, double map_y) const {
  if (!result_) return kNaN;
  const Eigen::Vector2i cell = result_->map.grid.cellOf(map_x, map_y);
  if (!result_->map.grid.inside(cell.x(), cell.y())) return kNaN;
  return result_->map.yawDegrees(cell.x(), cell.y());
}

double MapView::passageWidthAt(double map_x, double map_y) const {
  if (!result_) return kNaN;
  const TraversabilityMap& map = result_->map;
  const Eigen::Vector2i cell = map.grid.cellOf(map_x, map_y);
  if (!map.grid.inside(cell.x(), cell.y()) || blocksPassage(map, cell.x(), cell.y())) return kNaN;
  // The passage runs along the direction with the longest free run through the point; its width
  // is the free run across that direction (both ways to the first blocking cell).
  const double step = map.grid.resolution / 2;
  const int max_steps = int(kPassageSearch / step);
  auto freeRun = [&](double direction) {
    double total = 0.0;
    for (const double sign : {1.0, -1.0}) {
      int k = 1;
      for (; k <= max_steps; ++k) {
        const Eigen::Vector2i c = map.grid.cellOf(map_x + sign * k * step * std::cos(direction),
                                                  map_y + sign * k * step * std::sin(direction));
        if (!map.grid.inside(c.x(), c.y()) || blocksPassage(map, c.x(), c.y())) break;
      }
      total += (k - 0.5) * step;
    }
    return total;
  };
  double axis = 0.0, longest = -1.0;
  for (int k = 0; k < kPassageDirections; ++k) {
    const double direction = k * M_PI / kPassageDirections;
    const double run = freeRun(direction);
    if (run > longest) {
      longest = run;
      axis = direction;
    }
  }
  const double width = freeRun(axis + M_PI / 2);
  const double narrowest = width < kNarrowPassage ? width : kNaN;
  return narrowest;
}

void MapView::paintEvent(QPaintEvent*) {
  QPainter painter(this);
  if (!result_ || image_.isNull()) {
    painter.setPen(Qt::lightGray);
    painter.drawText(rect(), Qt::AlignCenter | Qt::TextWordWrap,
                     tr("No traversability map.\nOpen a scan (Ctrl+O), drop one here, or acquire "
                        "one in the Scanner panel."));
    return;
  }
  const MapGrid& grid = result_->map.grid;
  const QTransform to_widget = mapToPicture(pixels_per_metre_, offset_);
  const QPointF top_left =
      toWidget(grid.origin.x(), grid.origin.y() + grid.height * grid.resolution);
  const QSizeF size(grid.width * grid.resolution * pixels_per_metre_,
                    grid.height * grid.resolution * pixels_per_metre_);
  if (isStale()) painter.setOpacity(0.35);
  painter.drawImage(QRectF(top_left, size),
                    isStale() ? image_.convertToFormat(QImage::Format_Grayscale8) : image_);
  painter.setOpacity(1.0);
  drawMetreGrid(painter, to_widget, rect());
  drawMapAxes(painter, to_widget);
  drawPath(painter, to_widget, path_, result_->robot);
  if (goal_) drawGoal(painter, to_widget.map(*goal_), goal_reachable_);
  // Without ground the robot has no place on the map: nothing to draw.
  if (result_->map.robot_orientation >= 0)
    drawRobot(painter, to_widget, robot_pose_, result_->robot);
  if (cursor_inside_ && !measuring_) drawFootprintAtCursor(painter);
  if (measure_points_.size() == 2)
    drawMeasurement(painter, to_widget, measure_points_[0], measure_points_[1],
                    measure_uncertainty_);
  else if (measure_points_.size() == 1 && cursor_inside_)
    drawMeasurement(painter, to_widget, measure_points_[0], cursor_map_, 1.0 / pixels_per_metre_);

  drawScaleBar(painter, QPointF(14, height() - 12), pixels_per_metre_);
  drawLegend(painter, QPoint(10, 10), palette_);
  drawNorthArrow(painter, QPointF(width() - 24, 44));

  if (isStale()) {
    const QRect band(0, height() / 2 - 24, width(), 48);
    painter.fillRect(band, QColor(0, 0, 0, 200));
    painter.setPen(QColor(255, 210, 80));
    QFont font = painter.font();
    font.setBold(true);
    painter.setFont(font);
    painter.drawText(band, Qt::AlignCenter | Qt::TextWordWrap, stale_note_);
  }
}

void MapView::drawFootprintAtCursor(QPainter& painter) const {
  // The robot's footprint at the cursor, in an orientation that fits there.
  const MapGrid& grid = result_->map.grid;
  const Eigen::Vector2i cell = grid.cellOf(cursor_map_.x(), cursor_map_.y());
  if (!grid.inside(cell.x(), cell.y())) return;
  const double yaw = result_->map.yawDegrees(cell.x(), cell.y());
  painter.save();
  painter.translate(toWidget(cursor_map_.x(), cursor_map_.y()));
  painter.rotate(-(std::isnan(yaw) ? 0.0 : yaw));
  painter.setPen(QPen(std::isnan(yaw) ? Qt::red : Qt::white, 1.5, Qt::DashLine));
  painter.setBrush(Qt::NoBrush);
  const double length = result_->robot.length * pixels_per_metre_,
               width = result_->robot.width * pixels_per_metre_;
  painter.drawRect(QRectF(-length / 2, -width / 2, length, width));
  painter.restore();
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
  pressed_ = true;
  dragged_ = false;
  press_position_ = last_drag_ = event->pos();
}

void MapView::mouseMoveEvent(QMouseEvent* event) {
  if (pressed_) {
    if ((event->pos() - press_position_).manhattanLength() > kClickSlopPx) dragged_ = true;
    if (dragged_) offset_ += event->pos() - last_drag_;
    last_drag_ = event->pos();
  }
  cursor_map_ = toMap(event->pos());
  cursor_inside_ = true;
  emit hovered(cursor_map_.x(), cursor_map_.y(), describe(cursor_map_.x(), cursor_map_.y()));
  update();
}

void MapView::mouseReleaseEvent(QMouseEvent* event) {
  const bool click = pressed_ && !dragged_;
  pressed_ = false;
  if (!click || !result_) return;
  const QPointF map = toMap(event->pos());
  if (measuring_) {
    if (measure_points_.size() == 2) measure_points_.clear();
    measure_points_.push_back(map);
    if (measure_points_.size() == 2) {
      // Good to the size of a pixel at the zoom the clicks were made at, whatever zoom follows.
      measure_uncertainty_ = 1.0 / pixels_per_metre_;
      emit measured(std::hypot(measure_points_[1].x() - measure_points_[0].x(),
                               measure_points_[1].y() - measure_points_[0].y()),
                    measure_uncertainty_);
    }
    update();
    return;
  }
  emit clicked(map.x(), map.y());
}

void MapView::leaveEvent(QEvent*) {
  cursor_inside_ = false;
  emit left();
  update();
}

void MapView::resizeEvent(QResizeEvent* event) {
  // Keep the scale and the map point at the centre; only the very first size fits the map.
  if (!fitted_) {
    fit();
    return;
  }
  const QPointF shift(double(event->size().width() - event->oldSize().width()) / 2,
                      double(event->size().height() - event->oldSize().height()) / 2);
  if (event->oldSize().isValid()) offset_ += shift;
}

}  // namespace clearway::ui
