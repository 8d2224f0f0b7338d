#include "scene_props.h"

#include <vtkActor.h>
#include <vtkActor2D.h>
#include <vtkBillboardTextActor3D.h>
#include <vtkCellArray.h>
#include <vtkCoordinate.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>

#include "clearway/point_class.h"
#include "clearway/scene/scene_geometry.h"
#include "clearway/ui/map_drawing.h"

namespace clearway::ui::scene {
namespace {

// Large clouds are thinned for display so the view stays fluid.
constexpr std::size_t kMaxDisplayedPoints = 400'000;
// Points sampled per axis for the robust extent (enough for stable percentiles).
constexpr std::size_t kExtentSamples = 20'000;
// The grid lies this far below the ground so it never flickers through the ground triangles.
constexpr double kGridDrop = 0.02;
// At most this many grid labels along an axis: a KITTI frame's 100 m at 5 m steps ran its labels
// into one another ("-45 m40 m35 m...") in a top view at 1366 x 768.
constexpr double kMaxLabelsPerAxis = 12.0;
// Grid labels float this far above the ground so the ground never hides them [m].
constexpr double kLabelLift = 0.1;
// Footprints along the path every this many metres.
constexpr double kFootprintSpacing = 0.5;

// The 3D legend's rows [px].
constexpr int kLegendMarginPx = 10, kLegendRowPx = 22;

// Colours by height: blue low .. yellow high, over this band of map heights [m].
constexpr double kHeightLow = -0.5, kHeightBand = 3.0;

struct MeshBuilder {
  vtkNew<vtkPoints> points;
  vtkNew<vtkUnsignedCharArray> colours;
  vtkNew<vtkCellArray> cells;
  MeshBuilder() { colours->SetNumberOfComponents(3); }

  vtkIdType add(const Eigen::Vector3d& p, QColor colour) {
    const unsigned char rgb[3] = {static_cast<unsigned char>(colour.red()),
                                  static_cast<unsigned char>(colour.green()),
                                  static_cast<unsigned char>(colour.blue())};
    colours->InsertNextTypedTuple(rgb);
    return points->InsertNextPoint(p.x(), p.y(), p.z());
  }

  void box(const Eigen::Vector3d& centre, const Eigen::Matrix3d& axes, const Eigen::Vector3d& half,
           QColor colour) {
    vtkIdType ids[8];
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3d sign((corner & 1) ? 1. : -1., (corner & 2) ? 1. : -1.,
                                 (corner & 4) ? 1. : -1.);
      ids[corner] = add(centre + axes * sign.cwiseProduct(half), colour);
    }
    static constexpr int kFaces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6},
                                          {0, 1, 4}, {1, 5, 4}, {2, 6, 3}, {3, 6, 7},
                                          {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    for (const auto& f : kFaces) {
      const vtkIdType t[3] = {ids[f[0]], ids[f[1]], ids[f[2]]};
      cells->InsertNextCell(3, t);
    }
  }

  vtkSmartPointer<vtkActor> actor(bool lines = false, bool vertices = false) {
    auto data = vtkSmartPointer<vtkPolyData>::New();
    data->SetPoints(points);
    if (vertices)
      data->SetVerts(cells);
    else if (lines)
      data->SetLines(cells);
    else
      data->SetPolys(cells);
    data->GetPointData()->SetScalars(colours);
    auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
    mapper->SetInputData(data);
    mapper->SetScalarModeToUsePointData();
    mapper->SetColorModeToDirectScalars();
    auto result = vtkSmartPointer<vtkActor>::New();
    result->SetMapper(mapper);
    return result;
  }
};

double percentile(std::vector<double>& values, double fraction) {
  if (values.empty()) return 0.0;
  const auto k = std::size_t(fraction * double(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(k), values.end());
  return values[k];
}

// Where a label's text lies from its anchor.
enum class Anchor { kCentre, kTextRightOfIt, kTextAboveIt };

vtkSmartPointer<vtkProp> label3d(const QString& text, const Eigen::Vector3d& at, QColor colour,
                                 int size = 13, Anchor anchor = Anchor::kCentre) {
  auto label = vtkSmartPointer<vtkBillboardTextActor3D>::New();
  label->SetInput(text.toUtf8().constData());
  label->SetPosition(at.x(), at.y(), at.z());
  label->GetTextProperty()->SetFontSize(size);
  label->GetTextProperty()->SetColor(colour.redF(), colour.greenF(), colour.blueF());
  label->GetTextProperty()->SetJustificationToCentered();
  if (anchor == Anchor::kTextRightOfIt) label->GetTextProperty()->SetJustificationToLeft();
  if (anchor == Anchor::kTextAboveIt) label->GetTextProperty()->SetVerticalJustificationToBottom();
  // A billboard's bounds are only known once it has been drawn: left out of the camera's
  // clipping range and framing, they cannot clip the scene away.
  label->UseBoundsOff();
  return label;
}

Eigen::Matrix3d yawAxes(double yaw) {
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

}  // namespace

CloudProps cloudProps(const Scan& scan, const Eigen::Isometry3d& map_from_scanner,
                      const std::vector<PointClass>* classes, SceneView::CloudColour colour) {
  MeshBuilder cloud, ceiling;
  const std::size_t stride = std::max<std::size_t>(1, scan.size() / kMaxDisplayedPoints);
  const std::size_t extent_stride = std::max<std::size_t>(1, scan.size() / kExtentSamples);
  std::vector<double> xs, ys, zs;
  float max_intensity = 1.0F;
  for (float value : scan.intensity)
    max_intensity = std::max(max_intensity, value);
  for (std::size_t i = 0; i < scan.size(); i += stride) {
    if (!scan.isValid(i)) continue;
    const PointClass point_class =
        classes && i < classes->size() ? (*classes)[i] : PointClass::kNone;
    const Point3f& raw = scan.points[i];
    const Eigen::Vector3d p = map_from_scanner * Eigen::Vector3d(raw.x, raw.y, raw.z);
    if (i % extent_stride < stride) {
      xs.push_back(p.x());
      ys.push_back(p.y());
      zs.push_back(p.z());
    }
    if (point_class == PointClass::kGround) continue;
    QColor rgb;
    if (colour == SceneView::CloudColour::kHeight) {
      const double t = std::clamp((p.z() - kHeightLow) / kHeightBand, 0.0, 1.0);
      rgb = QColor(int(40 + 215 * t), int(80 + 150 * t), int(220 - 180 * t));
    } else if (colour == SceneView::CloudColour::kClass && classes) {
      // none, ground, wall, ceiling, obstacle, stairs
      static const QColor kClassColours[6] = {{128, 128, 128}, {0, 158, 115},  {140, 20, 20},
                                              {120, 144, 156}, {190, 120, 20}, {204, 121, 167}};
      rgb = kClassColours[std::min<std::size_t>(std::size_t(point_class), 5)];
    } else {
      const int grey =
          scan.intensity.empty()
              ? 170
              : int(60 + 170 * std::clamp(scan.intensity[i] / max_intensity, 0.0F, 1.0F));
      rgb = QColor(grey, grey, grey);
    }
    MeshBuilder& target = point_class == PointClass::kCeiling ? ceiling : cloud;
    const vtkIdType id = target.add(p, rgb);
    target.cells->InsertNextCell(1, &id);
  }
  CloudProps props;
  props.cloud = cloud.actor(false, true);
  props.cloud->GetProperty()->SetPointSize(2);
  if (classes) {
    props.ceiling = ceiling.actor(false, true);
    props.ceiling->GetProperty()->SetPointSize(2);
  }
  if (!xs.empty())
    props.robust = {percentile(xs, kRobustLow), percentile(xs, kRobustHigh),
                    percentile(ys, kRobustLow), percentile(ys, kRobustHigh),
                    percentile(zs, kRobustLow), percentile(zs, kRobustHigh)};
  return props;
}

vtkSmartPointer<vtkActor> groundActor(const PipelineResult& result, PaletteKind palette,
                                      const std::vector<std::uint8_t>& reachable) {
  MeshBuilder mesh;
  const SceneGeometry& ground = result.scene;
  const Eigen::Isometry3d& to_map = result.analysis->map_from_scanner;
  const MapGrid& grid = result.map.grid;
  const bool has_reach = reachable.size() == result.map.labels.size();
  for (std::size_t i = 0; i < ground.vertices.size(); ++i) {
    const Eigen::Vector3d p = to_map * ground.vertices[i].cast<double>();
    QColor colour = cellColour(ground.vertex_labels[i], palette);
    if (has_reach) {
      const Eigen::Vector2i cell = grid.cellOf(p.x(), p.y());
      if (grid.inside(cell.x(), cell.y()) && !reachable[grid.index(cell.x(), cell.y())])
        colour = colour.darker(250);
    }
    mesh.add(p, colour);
  }
  for (const auto& t : ground.triangles) {
    const vtkIdType ids[3] = {vtkIdType(t[0]), vtkIdType(t[1]), vtkIdType(t[2])};
    mesh.cells->InsertNextCell(3, ids);
  }
  return mesh.actor();
}

vtkSmartPointer<vtkActor> boxesActor(const std::vector<SceneBox>& boxes,
                                     const Eigen::Isometry3d& map_from_scanner,
                                     PaletteKind palette) {
  MeshBuilder mesh;
  for (const SceneBox& box : boxes)
    mesh.box(map_from_scanner * box.center.cast<double>(),
             map_from_scanner.linear() * box.axes.cast<double>(), box.half_size.cast<double>(),
             cellColour(box.label, palette));
  return mesh.actor();
}

std::vector<vtkSmartPointer<vtkProp>> gridProps(const Bounds& bounds) {
  MeshBuilder lines;
  const double x0 = std::floor(bounds[0]), x1 = std::ceil(bounds[1]);
  const double y0 = std::floor(bounds[2]), y1 = std::ceil(bounds[3]);
  const QColor colour(110, 110, 120);
  for (double x = x0; x <= x1; x += 1.0) {
    const vtkIdType ids[2] = {lines.add({x, y0, -kGridDrop}, colour),
                              lines.add({x, y1, -kGridDrop}, colour)};
    lines.cells->InsertNextCell(2, ids);
  }
  for (double y = y0; y <= y1; y += 1.0) {
    const vtkIdType ids[2] = {lines.add({x0, y, -kGridDrop}, colour),
                              lines.add({x1, y, -kGridDrop}, colour)};
    lines.cells->InsertNextCell(2, ids);
  }
  std::vector<vtkSmartPointer<vtkProp>> props{lines.actor(true)};
  const double step = roundStep(std::max(x1 - x0, y1 - y0), kMaxLabelsPerAxis);
  const QColor text(200, 200, 210);
  // Inside the grid's edges: centred on its edge, the outermost labels lost their first characters
  // (a minus sign) where the view ends with the grid.
  for (double x = std::ceil(x0 / step) * step; x <= x1; x += step)
    if (x != 0.0)
      props.push_back(
          label3d(QString("%1 m").arg(x), {x, y0, kLabelLift}, text, 12, Anchor::kTextAboveIt));
  for (double y = std::ceil(y0 / step) * step; y <= y1; y += step)
    if (y != 0.0)
      props.push_back(
          label3d(QString("%1 m").arg(y), {x0, y, kLabelLift}, text, 12, Anchor::kTextRightOfIt));
  return props;
}

std::vector<vtkSmartPointer<vtkProp>> axesProps() {
  MeshBuilder lines;
  const std::pair<Eigen::Vector3d, QColor> axes[] = {
      {Eigen::Vector3d::UnitX(), QColor(230, 60, 60)},
      {Eigen::Vector3d::UnitY(), QColor(60, 200, 90)},
      {Eigen::Vector3d::UnitZ(), QColor(80, 140, 255)}};
  // Unlabelled: the legend names the colours (billboard labels on the axes' tips glitched under
  // llvmpipe, drawn stretched down to the view's edge).
  for (const auto& [direction, colour] : axes) {
    const vtkIdType ids[2] = {lines.add(Eigen::Vector3d::Zero(), colour),
                              lines.add(direction, colour)};
    lines.cells->InsertNextCell(2, ids);
  }
  auto actor = lines.actor(true);
  actor->GetProperty()->SetLineWidth(4);
  return {actor};
}

std::vector<vtkSmartPointer<vtkProp>> robotProps(const PathPose& pose, const RobotParams& robot,
                                                 QColor colour, double opacity) {
  MeshBuilder body, arrow;
  const Eigen::Matrix3d axes = yawAxes(pose.yaw);
  body.box({pose.x, pose.y, robot.height / 2}, axes,
           {robot.length / 2, robot.width / 2, robot.height / 2}, colour);
  // Heading: a flat arrow on the ground from the centre to beyond the front.
  const Eigen::Vector3d centre(pose.x, pose.y, 0.03);
  const Eigen::Vector3d forward = axes.col(0), left = axes.col(1);
  const double reach = robot.length * 0.8, wing = std::min(0.25, robot.width / 3);
  const QColor white(255, 255, 255);
  const vtkIdType a = arrow.add(centre - forward * 0.1 + left * wing / 3, white);
  const vtkIdType b = arrow.add(centre - forward * 0.1 - left * wing / 3, white);
  const vtkIdType c = arrow.add(centre + forward * (reach - wing) - left * wing / 3, white);
  const vtkIdType d = arrow.add(centre + forward * (reach - wing) + left * wing / 3, white);
  const vtkIdType e = arrow.add(centre + forward * (reach - wing) + left * wing, white);
  const vtkIdType f = arrow.add(centre + forward * reach, white);
  const vtkIdType g = arrow.add(centre + forward * (reach - wing) - left * wing, white);
  for (const auto& t : {std::array{a, b, c}, {a, c, d}, {e, g, f}}) {
    const vtkIdType ids[3] = {t[0], t[1], t[2]};
    arrow.cells->InsertNextCell(3, ids);
  }
  // The box's twelve edges, so a faint body still reads as a box.
  MeshBuilder edges;
  const Eigen::Vector3d half(robot.length / 2, robot.width / 2, robot.height / 2);
  const Eigen::Vector3d middle(pose.x, pose.y, robot.height / 2);
  // Returns a vector, not an Eigen expression that would refer to the lambda's dead locals.
  auto corner = [&](int k) -> Eigen::Vector3d {
    const Eigen::Vector3d sign((k & 1) ? 1. : -1., (k & 2) ? 1. : -1., (k & 4) ? 1. : -1.);
    return middle + axes * sign.cwiseProduct(half);
  };
  for (int from = 0; from < 8; ++from)
    for (const int bit : {1, 2, 4})
      if (!(from & bit)) {
        const vtkIdType ids[2] = {edges.add(corner(from), colour.lighter(150)),
                                  edges.add(corner(from | bit), colour.lighter(150))};
        edges.cells->InsertNextCell(2, ids);
      }
  auto edge_actor = edges.actor(true);
  edge_actor->GetProperty()->SetLineWidth(2);
  auto body_actor = body.actor();
  body_actor->GetProperty()->SetOpacity(opacity);
  return {body_actor, edge_actor, arrow.actor()};
}

std::vector<vtkSmartPointer<vtkProp>> pathProps(const std::vector<PathPose>& path,
                                                const RobotParams& robot) {
  if (path.empty()) return {};
  MeshBuilder line, feet;
  const QColor colour(90, 200, 255);
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const vtkIdType ids[2] = {line.add({path[i].x, path[i].y, 0.05}, colour),
                              line.add({path[i + 1].x, path[i + 1].y, 0.05}, colour)};
    line.cells->InsertNextCell(2, ids);
  }
  double since = kFootprintSpacing;
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (i > 0) since += std::hypot(path[i].x - path[i - 1].x, path[i].y - path[i - 1].y);
    if (since < kFootprintSpacing && i + 1 < path.size()) continue;
    feet.box({path[i].x, path[i].y, 0.01}, yawAxes(path[i].yaw),
             {robot.length / 2, robot.width / 2, 0.01}, colour);
    since = 0.0;
  }
  auto line_actor = line.actor(true);
  line_actor->GetProperty()->SetLineWidth(3);
  auto feet_actor = feet.actor();
  feet_actor->GetProperty()->SetOpacity(0.35);
  return {line_actor, feet_actor};
}

std::vector<vtkSmartPointer<vtkProp>> measurementProps(const Eigen::Vector3d& from,
                                                       const Eigen::Vector3d& to) {
  MeshBuilder line;
  const QColor white(255, 255, 255);
  const vtkIdType ids[2] = {line.add(from, white), line.add(to, white)};
  line.cells->InsertNextCell(2, ids);
  auto actor = line.actor(true);
  actor->GetProperty()->SetLineWidth(3);
  actor->GetProperty()->SetRenderLinesAsTubes(true);
  // Picked points are exact: written as the status bar writes a distance given exactly.
  return {actor, label3d(distanceInWords((to - from).norm(), 0.0),
                         (from + to) / 2 + Eigen::Vector3d(0, 0, 0.15), white, 16)};
}

std::vector<vtkSmartPointer<vtkProp>> legendProps(PaletteKind palette) {
  const std::pair<QColor, QString> entries[] = {
      {cellColour(CellLabel::kTraversable, palette), QObject::tr("traversable")},
      {cellColour(CellLabel::kCareful, palette), QObject::tr("careful")},
      {cellColour(CellLabel::kObstacle, palette),
       QObject::tr("low obstacle, sparse or unseen above")},
      {cellColour(CellLabel::kImpassable, palette), QObject::tr("impassable, walls")},
      {cellColour(CellLabel::kStairs, palette), QObject::tr("stairs, with care")},
      {QColor(40, 120, 255), QObject::tr("robot (arrow: heading)")},
      {QColor(60, 60, 66), QObject::tr("grid 1 m; axes x red, y green, z blue")}};
  std::vector<vtkSmartPointer<vtkProp>> props;
  int row = 0;
  for (const auto& [colour, name] : entries) {
    auto text = vtkSmartPointer<vtkTextActor>::New();
    text->SetInput(name.toUtf8().constData());
    // Rows in pixels below the view's top-left corner, whatever the view's size.
    vtkNew<vtkCoordinate> top_left;
    top_left->SetCoordinateSystemToNormalizedViewport();
    top_left->SetValue(0.0, 1.0);
    text->GetPositionCoordinate()->SetCoordinateSystemToDisplay();
    text->GetPositionCoordinate()->SetReferenceCoordinate(top_left);
    text->GetPositionCoordinate()->SetValue(kLegendMarginPx, -kLegendMarginPx - row * kLegendRowPx);
    ++row;
    vtkTextProperty* property = text->GetTextProperty();
    property->SetFontSize(14);
    property->SetBold(true);
    // The class colour as the background, the text in black or white on it: readable for every
    // class, dark red included.
    const QColor ink = colour.lightness() > 110 ? QColor(Qt::black) : QColor(Qt::white);
    property->SetColor(ink.redF(), ink.greenF(), ink.blueF());
    property->SetBackgroundColor(colour.redF(), colour.greenF(), colour.blueF());
    property->SetBackgroundOpacity(0.9);
    property->SetVerticalJustificationToTop();
    props.push_back(text);
  }
  return props;
}

vtkSmartPointer<vtkProp> noticeProp(const QString& text, QColor colour) {
  auto actor = vtkSmartPointer<vtkTextActor>::New();
  actor->SetInput(text.toUtf8().constData());
  actor->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  actor->GetPositionCoordinate()->SetValue(0.5, 0.5);
  vtkTextProperty* property = actor->GetTextProperty();
  property->SetFontSize(18);
  property->SetBold(true);
  property->SetJustificationToCentered();
  property->SetVerticalJustificationToCentered();
  property->SetColor(colour.redF(), colour.greenF(), colour.blueF());
  property->SetBackgroundColor(0, 0, 0);
  property->SetBackgroundOpacity(0.7);
  return actor;
}

}  // namespace clearway::ui::scene
