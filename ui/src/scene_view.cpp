#include "clearway/ui/scene_view.h"

#include <QVTKOpenGLNativeWidget.h>
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellPicker.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkNew.h>
#include <vtkProp.h>
#include <vtkProperty.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>

#include <QGuiApplication>
#include <QImage>
#include <QLabel>
#include <QSurfaceFormat>
#include <QVBoxLayout>
#include <cmath>
#include <map>

#include "clearway/point_class.h"
#include "scene_interaction.h"
#include "scene_props.h"

namespace clearway::ui {
namespace {

using Props = std::vector<vtkSmartPointer<vtkProp>>;

// The operator's camera: this far behind the robot and this high, looking at a point this far
// ahead of it on the ground [m]; never higher than this far under the top of the robust extent
// (under most ceilings).
constexpr double kEyeBehind = 1.5, kEyeHeight = 2.6, kLookAhead = 6.0, kUnderCeiling = 0.3;
constexpr double kOperatorViewAngle = 60.0;
// Without a heading from the engine the camera looks at the scene's middle when it is at least
// this far from the robot [m].
constexpr double kMinLookDistance = 1.0;
// Orthographic views leave this margin around the robust extent.
constexpr double kFrameMargin = 1.15;
// Far cameras for orthographic views stand this far off the scene [m].
constexpr double kOrthoDistance = 100.0;
const QColor kRobotColour(40, 120, 255);
// The robot's box is see-through: the operator looks past it.
constexpr double kRobotOpacity = 0.15;
// Picking tolerance, as a fraction of the window's diagonal (points are small targets).
constexpr double kPickTolerance = 0.005;

}  // namespace

struct SceneView::Private {
  QVTKOpenGLNativeWidget* widget = nullptr;
  QLabel* placeholder = nullptr;
  vtkSmartPointer<vtkGenericOpenGLRenderWindow> window;
  vtkSmartPointer<vtkRenderer> renderer;
  std::shared_ptr<const Scan> scan;
  std::shared_ptr<const PipelineResult> result;
  CloudColour cloud_colour = CloudColour::kRemission;
  PaletteKind palette = PaletteKind::kColourBlindSafe;
  CameraView camera_view = CameraView::kBehind;
  std::map<Layer, Props> layers;
  std::map<Layer, bool> visible = {{Layer::kCloud, true},   {Layer::kGround, true},
                                   {Layer::kWalls, true},   {Layer::kObstacles, true},
                                   {Layer::kCeiling, true}, {Layer::kGrid, true}};
  Props overlays;  // robot, path, selection, measurement, legend, notices
  scene::Bounds robust{-5, 5, -5, 5, -1, 3};
  PathPose robot_pose;
  bool pose_from_engine = false;  // set once setRobotPose is called
  std::vector<PathPose> path;
  std::vector<std::uint8_t> reachable;
  QString stale_note;
  bool has_frame = false;
  bool measuring = false;
  std::vector<Eigen::Vector3d> measure_points;
  std::optional<PathPose> selected;
  bool selected_fits = true;

  Eigen::Isometry3d mapFromScanner() const {
    return has_frame ? result->analysis->map_from_scanner : Eigen::Isometry3d::Identity();
  }
  RobotParams robot() const { return result ? result->robot : RobotParams{}; }
};

void SceneView::prepareApplication() {
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
}

SceneView::SceneView(QWidget* parent) : QWidget(parent), d_(std::make_unique<Private>()) {
  setObjectName("sceneView");
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  // The offscreen platform has no OpenGL: say so instead of failing.
  if (QGuiApplication::platformName() == "offscreen" ||
      QGuiApplication::platformName() == "minimal") {
    d_->placeholder = new QLabel(tr("3D view unavailable: no OpenGL on this display (%1).")
                                     .arg(QGuiApplication::platformName()),
                                 this);
    d_->placeholder->setObjectName("sceneViewPlaceholder");
    d_->placeholder->setAlignment(Qt::AlignCenter);
    d_->placeholder->setWordWrap(true);
    layout->addWidget(d_->placeholder);
    return;
  }
  d_->widget = new QVTKOpenGLNativeWidget(this);
  d_->window = vtkSmartPointer<vtkGenericOpenGLRenderWindow>::New();
  d_->widget->setRenderWindow(d_->window);
  d_->renderer = vtkSmartPointer<vtkRenderer>::New();
  d_->renderer->SetBackground(0.12, 0.12, 0.14);
  d_->window->AddRenderer(d_->renderer);
  vtkNew<scene::ConsoleInteractorStyle> style;
  style->on_click = [this](int x, int y) { handleClick(x, y); };
  d_->window->GetInteractor()->SetInteractorStyle(style);
  layout->addWidget(d_->widget);
  clearScene();
}

SceneView::~SceneView() = default;

bool SceneView::hasRenderer() const {
  return d_->widget != nullptr;
}

void SceneView::render() {
  if (hasRenderer()) d_->window->Render();
}

void SceneView::clearScene() {
  d_->scan = nullptr;
  d_->result = nullptr;
  d_->has_frame = false;
  d_->path.clear();
  d_->reachable.clear();
  d_->selected.reset();
  d_->measure_points.clear();
  d_->stale_note.clear();
  if (!hasRenderer()) return;
  d_->renderer->RemoveAllViewProps();
  d_->layers.clear();
  d_->overlays.clear();
  auto hint = scene::noticeProp(tr("No scan yet.\nOpen one (Ctrl+O), drop one here,\nor acquire "
                                   "one in the Scanner panel."),
                                QColor(200, 200, 210));
  d_->overlays.push_back(hint);
  d_->renderer->AddViewProp(hint);
  render();
}

void SceneView::setScene(std::shared_ptr<const Scan> scan,
                         std::shared_ptr<const PipelineResult> result) {
  if (!scan) {
    clearScene();
    return;
  }
  const bool same_scan = scan == d_->scan && d_->result;
  if (!same_scan) {
    d_->path.clear();
    d_->reachable.clear();
    d_->selected.reset();
    d_->measure_points.clear();
  }
  d_->scan = std::move(scan);
  d_->result = std::move(result);
  d_->has_frame = d_->result && d_->result->trusted();
  d_->stale_note.clear();
  // The operator's view stands behind the robot: the robot of this result, not the last scan's
  // (the camera looked from another scan's robot place, into a wall). Without ground the robot
  // stands at the scanner's foot.
  if (d_->has_frame) {
    const RobotPose& pose = d_->result->map.robot_pose;
    d_->robot_pose = {pose.x, pose.y, pose.yaw};
  } else {
    d_->robot_pose = {};
  }
  // A guessed heading is one the box fits in, not where the robot looks.
  d_->pose_from_engine = d_->has_frame && d_->result->map.robot_heading_known;
  // A new robot size or new parameters keep the operator's camera; a new scan starts from the
  // operator's view.
  rebuild(same_scan);
}

void SceneView::rebuild(bool keep_camera) {
  if (!hasRenderer()) return;
  d_->renderer->RemoveAllViewProps();
  d_->layers.clear();
  if (d_->scan) {
    const PipelineResult* r = d_->result.get();
    auto cloud = scene::cloudProps(*d_->scan, d_->mapFromScanner(), r ? &r->point_classes : nullptr,
                                   d_->cloud_colour);
    d_->robust = cloud.robust;
    d_->layers[Layer::kCloud] = {cloud.cloud};
    if (cloud.ceiling) d_->layers[Layer::kCeiling] = {cloud.ceiling};
    if (d_->has_frame) {
      d_->layers[Layer::kGround] = {scene::groundActor(*r, d_->palette, d_->reachable)};
      d_->layers[Layer::kObstacles] = {
          scene::boxesActor(r->scene.obstacles, d_->mapFromScanner(), d_->palette)};
      // Walls are see-through so the ground behind them stays visible.
      auto walls = scene::boxesActor(r->scene.walls, d_->mapFromScanner(), d_->palette);
      walls->GetProperty()->SetOpacity(0.45);
      d_->layers[Layer::kWalls] = {walls};
    }
    d_->layers[Layer::kGrid] = scene::gridProps(d_->robust);
    for (auto& prop : scene::axesProps())
      d_->layers[Layer::kGrid].push_back(prop);
  }
  for (const auto& [layer, props] : d_->layers)
    for (const auto& prop : props)
      d_->renderer->AddViewProp(prop);
  applyLayerVisibility();
  d_->overlays.clear();
  rebuildOverlays();
  if (keep_camera) {
    d_->renderer->ResetCameraClippingRange();
    render();
  } else {
    setCameraView(CameraView::kBehind);
  }
}

void SceneView::rebuildOverlays() {
  if (!hasRenderer()) return;
  for (const auto& prop : d_->overlays)
    d_->renderer->RemoveViewProp(prop);
  d_->overlays.clear();
  auto add = [this](const Props& props) {
    for (const auto& prop : props) {
      d_->overlays.push_back(prop);
      d_->renderer->AddViewProp(prop);
    }
  };
  if (d_->has_frame) {
    add(scene::robotProps(d_->robot_pose, d_->robot(), kRobotColour, kRobotOpacity));
    add(scene::pathProps(d_->path, d_->robot()));
    if (d_->selected)
      add(scene::robotProps(*d_->selected, d_->robot(),
                            d_->selected_fits ? QColor(255, 255, 255) : QColor(140, 20, 20), 0.35));
  }
  if (d_->measure_points.size() == 2)
    add(scene::measurementProps(d_->measure_points[0], d_->measure_points[1]));
  if (d_->scan) add(scene::legendProps(d_->palette));
  if (!d_->stale_note.isEmpty()) add({scene::noticeProp(d_->stale_note, QColor(255, 210, 80))});
  if (d_->scan && d_->result && !d_->has_frame)
    add({scene::noticeProp(tr("No ground found: nothing is shown as traversable."),
                           QColor(255, 120, 120))});
}

void SceneView::applyLayerVisibility() {
  for (const auto& [layer, props] : d_->layers) {
    bool on = d_->visible[layer];
    // The ceiling would hide the inside from above.
    if (layer == Layer::kCeiling && d_->camera_view == CameraView::kTop) on = false;
    for (const auto& prop : props)
      prop->SetVisibility(on);
  }
}

void SceneView::showArrivingScan(std::shared_ptr<const Scan> so_far) {
  if (!so_far) return;
  const bool first = d_->result != nullptr || !d_->scan;
  d_->scan = std::move(so_far);
  if (first) {
    d_->result = nullptr;
    d_->has_frame = false;
    d_->stale_note.clear();
  }
  rebuild(!first);
}

void SceneView::setLayerVisible(Layer layer, bool visible) {
  d_->visible[layer] = visible;
  if (!hasRenderer()) return;
  applyLayerVisibility();
  render();
}

bool SceneView::layerVisible(Layer layer) const {
  return d_->visible.at(layer);
}

void SceneView::setCloudColour(CloudColour colour) {
  d_->cloud_colour = colour;
  rebuild(true);
}

void SceneView::setPaletteKind(PaletteKind palette) {
  d_->palette = palette;
  rebuild(true);
}

void SceneView::setRobotPose(double x, double y, double yaw) {
  d_->robot_pose = {x, y, yaw};
  d_->pose_from_engine = true;
  rebuildOverlays();
  render();
}

void SceneView::setPath(std::vector<PathPose> path) {
  d_->path = std::move(path);
  rebuildOverlays();
  render();
}

void SceneView::setReachable(std::vector<std::uint8_t> reachable) {
  d_->reachable = std::move(reachable);
  rebuild(true);
}

void SceneView::showRobotAt(double map_x, double map_y, double yaw_deg) {
  d_->selected = PathPose{map_x, map_y, std::isnan(yaw_deg) ? 0.0 : yaw_deg * M_PI / 180.0};
  d_->selected_fits = !std::isnan(yaw_deg);
  rebuildOverlays();
  render();
}

void SceneView::setStale(const QString& note) {
  d_->stale_note = note;
  rebuildOverlays();
  render();
}

void SceneView::setMeasuring(bool on) {
  d_->measuring = on;
  d_->measure_points.clear();
  rebuildOverlays();
  render();
}

bool SceneView::pickAt(QPoint widget_position) {
  if (!hasRenderer()) return false;
  const double ratio = d_->widget->devicePixelRatioF();
  const int x = int(widget_position.x() * ratio);
  const int y = int((d_->widget->height() - 1 - widget_position.y()) * ratio);
  return handleClick(x, y);
}

bool SceneView::handleClick(int x, int y) {
  vtkNew<vtkCellPicker> picker;
  picker->SetTolerance(kPickTolerance);
  if (!picker->Pick(x, y, 0, d_->renderer)) return false;
  double position[3];
  picker->GetPickPosition(position);
  const Eigen::Vector3d point(position[0], position[1], position[2]);
  if (d_->measuring) {
    if (d_->measure_points.size() == 2) d_->measure_points.clear();
    d_->measure_points.push_back(point);
    if (d_->measure_points.size() == 2)
      emit measured((d_->measure_points[1] - d_->measure_points[0]).norm());
    rebuildOverlays();
    render();
  }
  QString what = tr("no map here");
  if (d_->result && d_->has_frame) {
    const TraversabilityMap& map = d_->result->map;
    const Eigen::Vector2i cell = map.grid.cellOf(point.x(), point.y());
    if (map.grid.inside(cell.x(), cell.y())) {
      const auto name = labelName(map.label(cell.x(), cell.y()));
      what = tr("%1 m above the ground, over a %2 cell")
                 .arg(point.z(), 0, 'f', 2)
                 .arg(QString::fromUtf8(name.data(), int(name.size())));
    }
  }
  emit pointPicked(point.x(), point.y(), point.z(), what);
  return true;
}

std::shared_ptr<const Scan> SceneView::shownScan() const {
  return d_->scan;
}

std::array<double, 6> SceneView::robustBounds() const {
  return d_->robust;
}

SceneView::CameraView SceneView::cameraView() const {
  return d_->camera_view;
}

bool SceneView::isOrthographic() const {
  return hasRenderer() && d_->renderer->GetActiveCamera()->GetParallelProjection();
}

void SceneView::setCameraView(CameraView view) {
  d_->camera_view = view;
  if (!hasRenderer()) return;
  applyLayerVisibility();
  const scene::Bounds& b = d_->robust;
  const Eigen::Vector3d centre((b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2);
  vtkCamera* camera = d_->renderer->GetActiveCamera();
  const double aspect = std::max(1.0, double(width())) / std::max(1.0, double(height()));
  switch (view) {
    case CameraView::kBehind: {
      // Behind and above the robot, looking where it (and the scanner) looks.
      camera->SetParallelProjection(false);
      // Until the engine gives the robot a heading, look from the robot towards the middle of
      // what the scanner saw (in a corridor: along it, not into its side wall).
      const PathPose& pose = d_->robot_pose;
      const Eigen::Vector3d foot(pose.x, pose.y, 0.0);
      Eigen::Vector3d heading(std::cos(pose.yaw), std::sin(pose.yaw), 0.0);
      const Eigen::Vector3d to_scene(centre.x() - pose.x, centre.y() - pose.y, 0.0);
      if (!d_->pose_from_engine && to_scene.norm() > kMinLookDistance)
        heading = to_scene.normalized();
      const double height = std::max(0.8, std::min(kEyeHeight, b[5] - kUnderCeiling));
      const Eigen::Vector3d eye = foot - kEyeBehind * heading + Eigen::Vector3d(0, 0, height);
      const Eigen::Vector3d focus = foot + kLookAhead * heading;
      camera->SetPosition(eye.x(), eye.y(), eye.z());
      camera->SetFocalPoint(focus.x(), focus.y(), focus.z());
      camera->SetViewUp(0, 0, 1);
      camera->SetViewAngle(kOperatorViewAngle);
      break;
    }
    case CameraView::kTop:
      // Map +x right, +y up: the same as the 2D map.
      camera->SetParallelProjection(true);
      camera->SetFocalPoint(centre.x(), centre.y(), 0.0);
      camera->SetPosition(centre.x(), centre.y(), kOrthoDistance);
      camera->SetViewUp(0, 1, 0);
      camera->SetParallelScale(kFrameMargin *
                               std::max((b[3] - b[2]) / 2, (b[1] - b[0]) / 2 / aspect));
      break;
    case CameraView::kFront:
    case CameraView::kSide: {
      // Elevations: from behind the scanner along +x, or from the robot's left along -y.
      camera->SetParallelProjection(true);
      const bool front = view == CameraView::kFront;
      camera->SetFocalPoint(centre.x(), centre.y(), centre.z());
      camera->SetPosition(front ? centre.x() - kOrthoDistance : centre.x(),
                          front ? centre.y() : centre.y() + kOrthoDistance, centre.z());
      camera->SetViewUp(0, 0, 1);
      const double across = front ? b[3] - b[2] : b[1] - b[0];
      camera->SetParallelScale(kFrameMargin * std::max((b[5] - b[4]) / 2, across / 2 / aspect));
      break;
    }
  }
  d_->renderer->ResetCameraClippingRange();
  render();
}

void SceneView::resetCamera() {
  setCameraView(CameraView::kBehind);
}

QImage SceneView::renderedImage() {
  if (!hasRenderer()) return {};
  d_->renderer->ResetCameraClippingRange();
  d_->window->Render();
  return d_->widget->grabFramebuffer();
}

}  // namespace clearway::ui
