#pragma once

// Exact answers from the scene's geometry: where is the ground, and can a robot box stand at a
// place without touching anything. Used to judge traversability maps.

#include <Eigen/Core>
#include <optional>

#include "clearway/sim/ray_caster.h"
#include "clearway/sim/scene.h"

namespace clearway::eval {

class RobotFit {
 public:
  explicit RobotFit(const sim::Scene& scene);
  // Height of the walkable top surface (ground or stairs) below (x, y, from_z) in the world.
  std::optional<double> groundHeight(double x, double y, double from_z) const;
  // True when a robot box centred at (x, y) near height z, turned by yaw, stands on ground whose
  // height varies by no more than the robot's step between neighbouring samples, and its body
  // (from max_step above the ground to its height) touches no solid.
  bool fits(const sim::RobotBox& robot, const Eigen::Vector3d& center, double yaw) const;
  // Any of `orientations` yaws in [0, pi).
  bool fitsAnyOrientation(const sim::RobotBox& robot, const Eigen::Vector3d& center,
                          int orientations) const;

 private:
  const sim::Scene& scene_;
  sim::Scene walkable_;
  sim::RayCaster walkable_caster_;
};

}  // namespace clearway::eval
