#pragma once

// Scenes for the simulated RoSi: solid primitives with a class each, named places a robot may
// want to reach, and the passages (doors) between them with their exact sizes. Scenes load from
// and save to JSON (docs/SCENES.md); the built-in ones are parameterised builders.

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "clearway/point_class.h"

namespace clearway::sim {

enum class Shape { kBox, kCylinder };

struct Primitive {
  std::string name;
  Shape shape = Shape::kBox;
  PointClass point_class = PointClass::kObstacle;
  // Box: centre and full edge lengths in its own frame, turned by yaw/pitch/roll (deg, applied
  // z then y then x). Cylinder: centre of the axis, size = (diameter, diameter, length) along its
  // own z after the same rotation.
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d size = Eigen::Vector3d::Ones();
  double yaw_deg = 0.0;
  double pitch_deg = 0.0;
  double roll_deg = 0.0;
  double remission = 0.5;    // reflectivity in [0, 1]
  bool transparent = false;  // glass: the beam returns nothing

  Eigen::Matrix3d rotation() const;  // primitive frame -> world
  // Whether `point` (world) lies inside the solid, its surface excluded.
  bool holdsInside(const Eigen::Vector3d& point) const;
};

// A place a robot may be asked to reach (x, y on the floor at height z).
struct Place {
  std::string name;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
};

// An opening between two places with its clear width and height. Places joined by no passage
// are separate; places joined with width/height 0 are always connected (open floor).
struct Passage {
  std::string name;
  std::string from;
  std::string to;
  double width = 0.0;
  double height = 0.0;
  // Highest step on the way [m]: a robot that cannot climb it cannot pass.
  double step = 0.0;
};

struct Scene {
  std::string name;
  std::string description;
  std::vector<Primitive> primitives;
  std::vector<Place> places;
  std::vector<Passage> passages;
  // Where the scanner stands by default and which way its turntable axis points (world frame).
  Eigen::Vector3d scanner_position{0.0, 0.0, 1.0};
  Eigen::Vector3d scanner_axis{1.0, 0.0, 0.0};
};

// The robot the analytic answers are computed for.
struct RobotBox {
  double width = 0.85;
  double length = 1.2;
  double height = 1.5;
  double max_step = 0.1;
};

// Pairs of places the robot can travel between (each pair once, names ordered as in the scene).
std::vector<std::pair<std::string, std::string>> reachablePlaces(const Scene& scene,
                                                                 const RobotBox& robot);

}  // namespace clearway::sim
