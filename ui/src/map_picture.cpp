#include "clearway/ui/map_picture.h"

#include <QPainter>
#include <cmath>

namespace clearway::ui {
namespace {

// Room around the map for the legend column and the scale bar [px].
constexpr int kMargin = 24;
constexpr int kLegendWidth = 170;

}  // namespace

QImage renderMapPicture(const PipelineResult& result, double pixels_per_metre, PaletteKind palette,
                        const PathPose& robot, const std::vector<PathPose>& path) {
  const MapGrid& grid = result.map.grid;
  const double width_m = grid.width * grid.resolution, height_m = grid.height * grid.resolution;
  const int map_width = int(std::ceil(width_m * pixels_per_metre));
  const int map_height = int(std::ceil(height_m * pixels_per_metre));
  const int width = map_width + 2 * kMargin + kLegendWidth;
  const int height = std::max(map_height, 200) + 2 * kMargin;
  if (width > kMaxMapPictureSide || height > kMaxMapPictureSide || map_width <= 0) return {};
  QImage picture(width, height, QImage::Format_RGB32);
  picture.fill(QColor(40, 40, 40));
  QPainter painter(&picture);
  // Map (origin.x, origin.y + height) lands at the map area's top left.
  const QPointF origin(kMargin - grid.origin.x() * pixels_per_metre,
                       kMargin + (grid.origin.y() + height_m) * pixels_per_metre);
  const QTransform to_picture = mapToPicture(pixels_per_metre, origin);
  const QRectF map_area(kMargin, kMargin, map_width, map_height);
  painter.drawImage(map_area, mapImage(result.map, palette));
  drawMetreGrid(painter, to_picture, map_area);
  drawMapAxes(painter, to_picture);
  drawPath(painter, to_picture, path, result.robot);
  drawRobot(painter, to_picture, robot, result.robot);
  const int legend_x = kMargin * 2 + map_width;
  const int legend_height = drawLegend(painter, QPoint(legend_x, kMargin), palette);
  drawNorthArrow(painter, QPointF(legend_x + 20, kMargin + legend_height + 50));
  drawScaleBar(painter, QPointF(legend_x, kMargin + legend_height + 110), pixels_per_metre,
               std::min(140.0, double(kLegendWidth - 20)));
  return picture;
}

}  // namespace clearway::ui
