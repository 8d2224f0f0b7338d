#pragma once

// The 2D traversability map pane: the map image with zoom (wheel) and pan (drag), a scale bar and
// a legend, a readout of the cell under the cursor (map x/y, class, why it is red) and the robot's
// footprint drawn at the cursor in the orientation that fits.

#include <QImage>
#include <QWidget>
#include <memory>

#include "clearway/pipeline.h"

namespace clearway::ui {

class MapView : public QWidget {
  Q_OBJECT

 public:
  explicit MapView(QWidget* parent = nullptr);

  void setResult(std::shared_ptr<const PipelineResult> result);
  void clear();
  // What the cell under a map position is, in words ("traversable", "impassable: too narrow").
  QString describe(double map_x, double map_y) const;
  const QImage& image() const { return image_; }
  // The orientation [deg] the robot fits in at a map position; NaN where it fits in none.
  double yawAt(double map_x, double map_y) const;

 signals:
  // The operator hovered (or clicked) a map position.
  void hovered(double map_x, double map_y, const QString& description);
  void clicked(double map_x, double map_y);

 protected:
  void paintEvent(QPaintEvent* event) override;
  void wheelEvent(QWheelEvent* event) override;
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void mouseReleaseEvent(QMouseEvent* event) override;
  void resizeEvent(QResizeEvent* event) override;

 private:
  void fitToView();
  QPointF toMap(const QPointF& widget) const;
  QPointF toWidget(double map_x, double map_y) const;

  std::shared_ptr<const PipelineResult> result_;
  QImage image_;
  double pixels_per_metre_ = 50.0;
  QPointF offset_;  // widget position of map (0, 0)
  QPoint last_drag_;
  bool dragging_ = false;
  bool fitted_ = false;
  QPointF cursor_map_;
  bool cursor_inside_ = false;
};

// The map as an image (row 0 = top), in the console's colours.
QImage mapImage(const TraversabilityMap& map);

}  // namespace clearway::ui
