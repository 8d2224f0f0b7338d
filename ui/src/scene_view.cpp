#include "clearway/ui/scene_view.h"

#include <QVTKOpenGLNativeWidget.h>
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkImageData.h>
#include <vtkInteractorStyleTrackballCamera.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkSphereSource.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>
#include <Eigen/Geometry>
#include <QGuiApplication>
#include <QImage>
#include <QLabel>
#include <QSurfaceFormat>
#include <QVBoxLayout>
#include <map>

#include "clearway/scene/scene_geometry.h"

namespace clearway::ui {
namespace {

// Large clouds are thinned for display so the view stays fluid.
constexpr std::size_t kMaxDisplayedPoints = 400'000;

// The cloud, thinned; points the result drew as ground triangles are left out. Coloured by
// remission (grey), by height along `up` (blue low .. yellow high) or by point class.
vtkSmartPointer<vtkPolyData> pointCloud(const Scan& scan, const std::vector<PointClass>* classes,
                                        SceneView::CloudColour mode, const Eigen::Vector3d& up,
                                        const std::vector<PointClass>* all_classes) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  auto colours = vtkSmartPointer<vtkUnsignedCharArray>::New();
  colours->SetNumberOfComponents(3);
  auto vertices = vtkSmartPointer<vtkCellArray>::New();
  const std::size_t stride = std::max<std::size_t>(1, scan.size() / kMaxDisplayedPoints);
  float max_intensity = 1.0F;
  for (float value : scan.intensity)
    max_intensity = std::max(max_intensity, value);
  for (std::size_t i = 0; i < scan.size(); i += stride) {
    if (!scan.isValid(i)) continue;
    if (classes && i < classes->size() && (*classes)[i] == PointClass::kGround) continue;
    const Point3f& p = scan.points[i];
    const vtkIdType id = points->InsertNextPoint(p.x, p.y, p.z);
    unsigned char rgb[3];
    if (mode == SceneView::CloudColour::kHeight) {
      const double t = std::clamp((Eigen::Vector3d(p.x, p.y, p.z).dot(up) + 2.0) / 5.0, 0.0, 1.0);
      rgb[0] = static_cast<unsigned char>(40 + 215 * t);
      rgb[1] = static_cast<unsigned char>(80 + 150 * t);
      rgb[2] = static_cast<unsigned char>(220 - 180 * t);
    } else if (mode == SceneView::CloudColour::kClass && all_classes && i < all_classes->size()) {
      // none, ground, wall, ceiling, obstacle, stairs
      static constexpr unsigned char kClassColours[6][3] = {{128, 128, 128}, {46, 160, 67},
                                                            {211, 47, 47},   {120, 144, 156},
                                                            {245, 140, 20},  {142, 68, 173}};
      const std::size_t c = std::min<std::size_t>(std::size_t((*all_classes)[i]), 5);
      for (int k = 0; k < 3; ++k)
        rgb[k] = kClassColours[c][k];
    } else {
      const auto grey = static_cast<unsigned char>(
          scan.intensity.empty()
              ? 170
              : 60 + 170 * std::clamp(scan.intensity[i] / max_intensity, 0.0F, 1.0F));
      rgb[0] = rgb[1] = rgb[2] = grey;
    }
    colours->InsertNextTypedTuple(rgb);
    vertices->InsertNextCell(1, &id);
  }
  auto cloud = vtkSmartPointer<vtkPolyData>::New();
  cloud->SetPoints(points);
  cloud->SetVerts(vertices);
  cloud->GetPointData()->SetScalars(colours);
  return cloud;
}

// A coloured mesh of ground triangles (may be empty) and boxes.
vtkSmartPointer<vtkPolyData> coloredMesh(const SceneGeometry* ground,
                                         const std::vector<SceneBox>& boxes) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  auto colours = vtkSmartPointer<vtkUnsignedCharArray>::New();
  colours->SetNumberOfComponents(3);
  auto triangles = vtkSmartPointer<vtkCellArray>::New();
  if (ground) {
    for (std::size_t i = 0; i < ground->vertices.size(); ++i) {
      const Eigen::Vector3f& v = ground->vertices[i];
      points->InsertNextPoint(v.x(), v.y(), v.z());
      colours->InsertNextTypedTuple(labelColour(ground->vertex_labels[i]).data());
    }
    for (const auto& t : ground->triangles) {
      const vtkIdType ids[3] = {vtkIdType(t[0]), vtkIdType(t[1]), vtkIdType(t[2])};
      triangles->InsertNextCell(3, ids);
    }
  }
  for (const SceneBox& box : boxes) {
    const auto rgb = labelColour(box.label);
    vtkIdType corner_ids[8];
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3f sign((corner & 1) ? 1.F : -1.F, (corner & 2) ? 1.F : -1.F,
                                 (corner & 4) ? 1.F : -1.F);
      const Eigen::Vector3f p = box.center + box.axes * sign.cwiseProduct(box.half_size);
      corner_ids[corner] = points->InsertNextPoint(p.x(), p.y(), p.z());
      colours->InsertNextTypedTuple(rgb.data());
    }
    static constexpr int kFaces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6},
                                          {0, 1, 4}, {1, 5, 4}, {2, 6, 3}, {3, 6, 7},
                                          {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    for (const auto& f : kFaces) {
      const vtkIdType ids[3] = {corner_ids[f[0]], corner_ids[f[1]], corner_ids[f[2]]};
      triangles->InsertNextCell(3, ids);
    }
  }
  auto mesh = vtkSmartPointer<vtkPolyData>::New();
  mesh->SetPoints(points);
  mesh->SetPolys(triangles);
  mesh->GetPointData()->SetScalars(colours);
  return mesh;
}

vtkSmartPointer<vtkActor> actorFor(vtkPolyData* data) {
  auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
  mapper->SetInputData(data);
  mapper->SetScalarModeToUsePointData();
  mapper->SetColorModeToDirectScalars();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  return actor;
}

}  // namespace

struct SceneView::Private {
  QVTKOpenGLNativeWidget* widget = nullptr;
  QLabel* placeholder = nullptr;
  vtkSmartPointer<vtkGenericOpenGLRenderWindow> window;
  vtkSmartPointer<vtkRenderer> renderer;
  std::shared_ptr<const Scan> scan;
  std::shared_ptr<const PipelineResult> result;
  CloudColour cloud_colour = CloudColour::kRemission;
  std::map<Layer, vtkSmartPointer<vtkActor>> layers;
  std::map<Layer, bool> visible = {{Layer::kCloud, true},
                                   {Layer::kGround, true},
                                   {Layer::kWalls, true},
                                   {Layer::kObstacles, true}};
  vtkSmartPointer<vtkActor> robot;
  // The map frame's up and forward in the scanner frame, for a camera that stands upright.
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d forward = Eigen::Vector3d::UnitX();
  bool has_frame = false;
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
  // Orbit with the left button, pan with the middle, zoom with the wheel.
  vtkNew<vtkInteractorStyleTrackballCamera> style;
  d_->window->GetInteractor()->SetInteractorStyle(style);
  layout->addWidget(d_->widget);
}

SceneView::~SceneView() = default;

bool SceneView::hasRenderer() const {
  return d_->widget != nullptr;
}

void SceneView::setScene(std::shared_ptr<const Scan> scan,
                         std::shared_ptr<const PipelineResult> result) {
  if (!hasRenderer()) return;
  const bool same_scan = scan && scan == d_->scan;
  d_->scan = std::move(scan);
  d_->result = std::move(result);
  d_->renderer->RemoveAllViewProps();
  d_->layers.clear();
  d_->robot = nullptr;
  const PipelineResult* r = d_->result.get();
  d_->has_frame = r && r->trusted();
  if (r) {
    d_->up = r->analysis.map_from_scanner.linear().row(2).transpose();
    d_->forward = r->analysis.map_from_scanner.linear().row(0).transpose();
  }
  if (d_->scan) {
    auto cloud = actorFor(pointCloud(*d_->scan, d_->has_frame ? &r->point_classes : nullptr,
                                     d_->cloud_colour, d_->up, r ? &r->point_classes : nullptr));
    cloud->GetProperty()->SetPointSize(2);
    d_->layers[Layer::kCloud] = cloud;
  }
  if (r) {
    d_->layers[Layer::kGround] = actorFor(coloredMesh(&r->scene, {}));
    d_->layers[Layer::kObstacles] = actorFor(coloredMesh(nullptr, r->scene.obstacles));
    // Walls are see-through so the ground behind them stays visible.
    auto walls = actorFor(coloredMesh(nullptr, r->scene.walls));
    walls->GetProperty()->SetOpacity(0.35);
    d_->layers[Layer::kWalls] = walls;
  }
  for (const auto& [layer, actor] : d_->layers) {
    actor->SetVisibility(d_->visible[layer]);
    d_->renderer->AddActor(actor);
  }
  vtkNew<vtkSphereSource> scanner;
  scanner->SetRadius(0.12);
  scanner->Update();
  auto marker = actorFor(scanner->GetOutput());
  marker->GetProperty()->SetColor(0.2, 0.6, 1.0);
  marker->GetMapper()->ScalarVisibilityOff();
  d_->renderer->AddActor(marker);
  // A new robot size keeps the operator's camera; a new scan starts from the default view.
  if (same_scan) {
    d_->window->Render();
  } else {
    resetCamera();
  }
}

void SceneView::showArrivingScan(std::shared_ptr<const Scan> so_far) {
  if (!hasRenderer() || !so_far) return;
  const bool first = d_->layers.find(Layer::kCloud) == d_->layers.end() || d_->result;
  if (first) {
    d_->renderer->RemoveAllViewProps();
    d_->layers.clear();
    d_->result = nullptr;
    d_->has_frame = false;
  } else {
    d_->renderer->RemoveActor(d_->layers[Layer::kCloud]);
  }
  d_->scan = so_far;
  auto cloud = actorFor(pointCloud(*so_far, nullptr, d_->cloud_colour, d_->up, nullptr));
  cloud->GetProperty()->SetPointSize(2);
  cloud->SetVisibility(d_->visible[Layer::kCloud]);
  d_->layers[Layer::kCloud] = cloud;
  d_->renderer->AddActor(cloud);
  if (first) {
    resetCamera();
  } else {
    d_->window->Render();
  }
}

void SceneView::setLayerVisible(Layer layer, bool visible) {
  d_->visible[layer] = visible;
  if (!hasRenderer()) return;
  if (const auto it = d_->layers.find(layer); it != d_->layers.end())
    it->second->SetVisibility(visible);
  d_->window->Render();
}

bool SceneView::layerVisible(Layer layer) const {
  return d_->visible.at(layer);
}

void SceneView::setCloudColour(CloudColour colour) {
  d_->cloud_colour = colour;
  if (hasRenderer() && d_->scan) {
    const auto scan = d_->scan;
    d_->scan = nullptr;  // rebuild, keeping the camera below
    vtkNew<vtkCamera> saved;
    saved->DeepCopy(d_->renderer->GetActiveCamera());
    setScene(scan, d_->result);
    d_->renderer->GetActiveCamera()->DeepCopy(saved);
    d_->window->Render();
  }
}

void SceneView::showRobotAt(double map_x, double map_y, double yaw_deg) {
  if (!hasRenderer() || !d_->result || !d_->has_frame) return;
  const PipelineResult& r = *d_->result;
  const Eigen::Isometry3d scanner_from_map = r.analysis.map_from_scanner.inverse();
  const double yaw = std::isnan(yaw_deg) ? 0.0 : yaw_deg * M_PI / 180.0;
  SceneBox box;
  box.label = std::isnan(yaw_deg) ? CellLabel::kImpassable : CellLabel::kTraversable;
  const Eigen::Vector3d centre(map_x, map_y, r.robot.height / 2);
  box.center = (scanner_from_map * centre).cast<float>();
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  box.axes = (scanner_from_map.linear() * turn).cast<float>();
  box.half_size = Eigen::Vector3f(float(r.robot.length / 2), float(r.robot.width / 2),
                                  float(r.robot.height / 2));
  if (d_->robot) d_->renderer->RemoveActor(d_->robot);
  d_->robot = actorFor(coloredMesh(nullptr, {box}));
  d_->robot->GetProperty()->SetOpacity(0.6);
  d_->renderer->AddActor(d_->robot);
  d_->window->Render();
}

void SceneView::setCameraView(CameraView view) {
  if (!hasRenderer()) return;
  const Eigen::Vector3d up = d_->has_frame ? d_->up : Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d forward = d_->has_frame ? d_->forward : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d side = up.cross(forward);
  Eigen::Vector3d eye = 2.5 * up - 6.0 * forward, view_up = up;
  switch (view) {
    case CameraView::kBehind:
      eye = 2.5 * up - 6.0 * forward;
      break;
    case CameraView::kTop:
      eye = 10.0 * up;
      view_up = forward;
      break;
    case CameraView::kFront:
      eye = -10.0 * forward + 0.5 * up;
      break;
    case CameraView::kSide:
      eye = 10.0 * side + 0.5 * up;
      break;
  }
  vtkCamera* camera = d_->renderer->GetActiveCamera();
  camera->SetFocalPoint(0, 0, 0);
  camera->SetPosition(eye.x(), eye.y(), eye.z());
  camera->SetViewUp(view_up.x(), view_up.y(), view_up.z());
  d_->renderer->ResetCamera();
  d_->window->Render();
}

void SceneView::resetCamera() {
  if (!hasRenderer()) return;
  vtkCamera* camera = d_->renderer->GetActiveCamera();
  camera->SetFocalPoint(0, 0, 0);
  if (d_->has_frame) {
    // From behind the scanner, a little above it, upright on the ground: under most ceilings.
    const Eigen::Vector3d eye = 2.5 * d_->up - 6.0 * d_->forward;
    camera->SetPosition(eye.x(), eye.y(), eye.z());
    camera->SetViewUp(d_->up.x(), d_->up.y(), d_->up.z());
  } else {
    camera->SetPosition(0, 0, 10);
    camera->SetViewUp(0, 1, 0);
  }
  d_->renderer->ResetCamera();
  d_->window->Render();
}

QImage SceneView::renderedImage() {
  if (!hasRenderer()) return {};
  d_->window->Render();
  return d_->widget->grabFramebuffer();
}

}  // namespace clearway::ui
