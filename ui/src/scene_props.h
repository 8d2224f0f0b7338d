#pragma once

// The VTK props of the 3D view, built from plain data in the map frame (x forward, y left, z up,
// ground at z = 0). Only scene_*.cpp include this header: VTK stays out of the public headers.

#include <vtkSmartPointer.h>

#include <Eigen/Geometry>
#include <QColor>
#include <QString>
#include <array>
#include <functional>
#include <vector>

#include "clearway/pipeline.h"
#include "clearway/scan.h"
#include "clearway/ui/map_drawing.h"
#include "clearway/ui/palette.h"
#include "clearway/ui/scene_view.h"

class vtkActor;
class vtkPolyData;
class vtkProp;
class vtkPropCollection;
class vtkRenderer;

namespace clearway::ui::scene {

// x0, x1, y0, y1, z0, z1 of the points between the kRobustLow and kRobustHigh percentiles per
// axis: the extent the camera frames, not stray far returns.
using Bounds = std::array<double, 6>;
inline constexpr double kRobustLow = 0.01;
inline constexpr double kRobustHigh = 0.99;

// A cloud split in the layers the view shows: everything but ground and ceiling, and the ceiling.
struct CloudProps {
  vtkSmartPointer<vtkActor> cloud;
  vtkSmartPointer<vtkActor> ceiling;  // null without classes
  Bounds robust{-5, 5, -5, 5, -1, 3};
};

// The cloud in the map frame (`map_from_scanner`), thinned; ground points (drawn as triangles)
// left out when `classes` is given, ceiling points in a layer of their own.
CloudProps cloudProps(const Scan& scan, const Eigen::Isometry3d& map_from_scanner,
                      const std::vector<PointClass>* classes, SceneView::CloudColour colour);

// Ground triangles coloured by their cells (dimmed where `reachable` says the robot cannot get),
// and boxes (walls, obstacles) in the map frame.
vtkSmartPointer<vtkActor> groundActor(const PipelineResult& result, PaletteKind palette,
                                      const std::vector<std::uint8_t>& reachable);
vtkSmartPointer<vtkActor> boxesActor(const std::vector<SceneBox>& boxes,
                                     const Eigen::Isometry3d& map_from_scanner,
                                     PaletteKind palette);

// A ground grid of 1 m cells over `bounds` with metre labels along both axes.
std::vector<vtkSmartPointer<vtkProp>> gridProps(const Bounds& bounds);
// The map frame's axes at its origin: x red, y green, z blue, 1 m long, labelled.
std::vector<vtkSmartPointer<vtkProp>> axesProps();
// The robot's box at a pose with an arrow along its heading.
std::vector<vtkSmartPointer<vtkProp>> robotProps(const PathPose& pose, const RobotParams& robot,
                                                 QColor colour, double opacity);
std::vector<vtkSmartPointer<vtkProp>> pathProps(const std::vector<PathPose>& path,
                                                const RobotParams& robot);
std::vector<vtkSmartPointer<vtkProp>> measurementProps(const Eigen::Vector3d& from,
                                                       const Eigen::Vector3d& to);
// The legend in the view's top-left corner (2D text in the class colours).
std::vector<vtkSmartPointer<vtkProp>> legendProps(PaletteKind palette);
// A line of 2D text centred on the view (hints, "previous scan" notes).
vtkSmartPointer<vtkProp> noticeProp(const QString& text, QColor colour);

}  // namespace clearway::ui::scene
