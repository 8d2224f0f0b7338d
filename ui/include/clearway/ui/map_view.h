#pragma once

// The 2D traversability map pane: the map image with zoom (wheel), pan (drag) and Fit, a metre
// grid, the map axes, the robot at its pose with its heading, a planned path as footprints, a
// measuring tool (two clicks), the legend and a scale bar; a readout of the cell under the cursor
// (map x/y, class, why it is red, the width of a narrow passage). A click (press and release
// without moving) selects a place; a drag only pans. While a new scan is acquired the shown map is
// greyed with a note of its age.

#include <QImage>
#include <QWidget>
#include <memory>
#include <optional>
#include <vector>

#include "clearway/pipeline.h"
#include "clearway/ui/map_drawing.h"
#include "clearway/ui/palette.h"

namespace clearway::ui {

class MapView : public QWidget {
  Q_OBJECT

 public:
  explicit MapView(QWidget* parent = nullptr);

  void setResult(std::shared_ptr<const PipelineResult> result);
  void clear();
  bool hasResult() const { return result_ != nullptr; }
  // What the cell under a map position is, in words ("traversable", "impassable: too narrow").
  QString describe(double map_x, double map_y) const;
  // The map as drawn, one pixel per cell (null without a result).
  const QImage& image() const { return image_; }
  // The orientation [deg] the robot fits in at a map position; NaN where it fits in none.
  double yawAt(double map_x, double map_y) const;
  // The free width [m] across a passage at a map position (across the orientation that fits
  // there), NaN where there is no passage narrower than kNarrowPassage.
  double passageWidthAt(double map_x, double map_y) const;
  static constexpr double kNarrowPassage = 2.0;

  // Where the robot stands (map frame). Until the engine reports a pose, the scanner's foot.
  void setRobotPose(double x, double y, double yaw);
  PathPose robotPose() const { return robot_pose_; }
  // The engine's "Can it get there?" path; empty hides it.
  void setPath(std::vector<PathPose> path);
  const std::vector<PathPose>& path() const { return path_; }
  // Marks the goal of "Can it get there?": a ring when reachable, a cross when not (the answer's
  // words alone did not say where the goal was). nullopt clears it.
  void setGoal(std::optional<QPointF> goal, bool reachable);
  std::optional<QPointF> goal() const { return goal_; }
  // Per map cell (the labels' indexing): 1 where the robot can get to. Free cells it cannot reach
  // are dimmed. Empty: reachability unknown, nothing dimmed.
  void setReachable(std::vector<std::uint8_t> reachable);
  const std::vector<std::uint8_t>& reachable() const { return reachable_; }
  void setPaletteKind(PaletteKind palette);
  PaletteKind paletteKind() const { return palette_; }
  // Greys the map with `note` over it ("Previous scan, 2 min old ..."); an empty note ends it.
  void setStale(const QString& note);
  bool isStale() const { return !stale_note_.isEmpty(); }
  // Whether the robot's footprint is drawn under the cursor.
  bool showsFootprintAtCursor() const { return cursor_inside_ && !measuring_; }
  // The next two clicks measure a distance (emitted as `measured`) instead of selecting.
  void setMeasuring(bool on);
  bool measuring() const { return measuring_; }
  // Measures between two map positions given exactly (the --measure option), as two clicks would.
  void measureBetween(const QPointF& from, const QPointF& to);
  // Shows the whole map.
  void fit();
  double pixelsPerMetre() const { return pixels_per_metre_; }
  // The widget position of a map position and back.
  QPointF toMap(const QPointF& widget) const;
  QPointF toWidget(double map_x, double map_y) const;

 signals:
  // The operator hovered a map position; `left` when the cursor left the map.
  void hovered(double map_x, double map_y, const QString& description);
  void left();
  // A click without dragging.
  void clicked(double map_x, double map_y);
  // A measured distance and how far off it may be: a click is placed to a pixel, so two clicks
  // are good to one pixel's size in metres at the zoom they were made at; 0 for measureBetween.
  void measured(double metres, double uncertainty_metres);

 protected:
  void paintEvent(QPaintEvent* event) override;
  void wheelEvent(QWheelEvent* event) override;
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void mouseReleaseEvent(QMouseEvent* event) override;
  void leaveEvent(QEvent* event) override;
  void resizeEvent(QResizeEvent* event) override;

 private:
  void rebuildImage();
  void drawFootprintAtCursor(QPainter& painter) const;

  std::shared_ptr<const PipelineResult> result_;
  QImage image_;
  PaletteKind palette_ = PaletteKind::kColourBlindSafe;
  double pixels_per_metre_ = 50.0;
  QPointF offset_;  // widget position of map (0, 0)
  QPoint press_position_;
  QPoint last_drag_;
  bool pressed_ = false;
  bool dragged_ = false;
  bool fitted_ = false;
  QPointF cursor_map_;
  bool cursor_inside_ = false;
  PathPose robot_pose_;
  std::vector<PathPose> path_;
  std::optional<QPointF> goal_;
  bool goal_reachable_ = false;
  std::vector<std::uint8_t> reachable_;
  QString stale_note_;
  bool measuring_ = false;
  std::vector<QPointF> measure_points_;  // 0, 1 or 2 map positions
  double measure_uncertainty_ = 0.0;     // of the two points' distance, as `measured` gave it
};

}  // namespace clearway::ui
