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
  // True when a robot box centred at (x, y) near height z, turned by yaw, stands on ground with no
  // step higher than the robot's between neighbouring samples, and its body (from max_step above
  // the ground to its height) touches no solid. A step is where one walkable surface meets
  // another: the two surfaces' heights apart where they meet, not the samples' (a ramp, or a
  // tilted slab, rises between samples without a step).
  bool fits(const sim::RobotBox& robot, const Eigen::Vector3d& center, double yaw) const;
  // Any of `orientations` yaws in [0, pi).
  bool fitsAnyOrientation(const sim::RobotBox& robot, const Eigen::Vector3d& center,
                          int orientations) const;

 private:
  // The walkable surface under a point: its height, which face of which primitive, its normal.
  struct GroundSample {
    double height = 0.0;
    int primitive = -1;
    int face = -1;
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  };
  std::optional<GroundSample> groundSample(double x, double y, double from_z) const;
  // The step between the ground samples at p and q (x, y), each sample's surface's height apart
  // where the two surfaces meet; nullopt where the ground between them is missing.
  std::optional<double> stepBetween(const Eigen::Vector2d& p, const GroundSample& at_p,
                                    const Eigen::Vector2d& q, const GroundSample& at_q,
                                    double from_z) const;

  const sim::Scene& scene_;
  sim::Scene walkable_;
  sim::RayCaster walkable_caster_;
};

}  // namespace clearway::eval
