#pragma once

// Exact ray casting against a scene's primitives.

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "clearway/sim/scene.h"

namespace clearway::sim {

struct RayHit {
  double distance = 0.0;
  int primitive = -1;  // index into Scene::primitives
  int face = -1;       // box: 0..5 = -x +x -y +y -z +z of the box frame; cylinder: 0 side, 1/2 caps
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // world, facing the ray
};

class RayCaster {
 public:
  explicit RayCaster(const Scene& scene);
  // Nearest hit along origin + t * direction (direction unit length) with t in (0, max_distance].
  std::optional<RayHit> cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                             double max_distance) const;

 private:
  struct Solid {
    Eigen::Matrix3d world_from_local;
    Eigen::Vector3d center;
    Eigen::Vector3d half_size;
    Shape shape;
    double bounding_radius;
  };
  std::vector<Solid> solids_;
};

}  // namespace clearway::sim
