#include "clearway/sim/ray_caster.h"

#include <cmath>
#include <limits>

namespace clearway::sim {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kEpsilon = 1e-9;

// Slab test in the box frame; returns entry distance and face, or nothing.
std::optional<std::pair<double, int>> hitBox(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                                             const Eigen::Vector3d& half) {
  double t_near = -kInfinity, t_far = kInfinity;
  int face = -1;
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(d[axis]) < kEpsilon) {
      if (std::abs(o[axis]) > half[axis]) return std::nullopt;
      continue;
    }
    double t0 = (-half[axis] - o[axis]) / d[axis];
    double t1 = (half[axis] - o[axis]) / d[axis];
    int entering_face = 2 * axis;  // -axis face
    if (t0 > t1) {
      std::swap(t0, t1);
      entering_face = 2 * axis + 1;
    }
    if (t0 > t_near) {
      t_near = t0;
      face = entering_face;
    }
    t_far = std::min(t_far, t1);
    if (t_near > t_far) return std::nullopt;
  }
  // A ray starting inside a solid sees nothing of it (the scanner is never inside a solid).
  if (t_near <= kEpsilon) return std::nullopt;
  return std::make_pair(t_near, face);
}

// Finite cylinder along the local z axis.
std::optional<std::pair<double, int>> hitCylinder(const Eigen::Vector3d& o,
                                                  const Eigen::Vector3d& d,
                                                  const Eigen::Vector3d& half) {
  const double radius = half.x();
  double best = kInfinity;
  int face = -1;
  const double a = d.x() * d.x() + d.y() * d.y();
  if (a > kEpsilon) {
    const double b = 2.0 * (o.x() * d.x() + o.y() * d.y());
    const double c = o.x() * o.x() + o.y() * o.y() - radius * radius;
    const double discriminant = b * b - 4 * a * c;
    if (discriminant >= 0) {
      const double t = (-b - std::sqrt(discriminant)) / (2 * a);
      if (t > kEpsilon && std::abs(o.z() + t * d.z()) <= half.z()) {
        best = t;
        face = 0;
      }
    }
  }
  if (std::abs(d.z()) > kEpsilon) {
    for (int cap = 0; cap < 2; ++cap) {
      const double z = cap == 0 ? -half.z() : half.z();
      const double t = (z - o.z()) / d.z();
      const Eigen::Vector3d p = o + t * d;
      if (t > kEpsilon && t < best && p.x() * p.x() + p.y() * p.y() <= radius * radius) {
        best = t;
        face = 1 + cap;
      }
    }
  }
  if (face < 0) return std::nullopt;
  return std::make_pair(best, face);
}

}  // namespace

RayCaster::RayCaster(const Scene& scene) {
  for (const Primitive& primitive : scene.primitives) {
    Solid solid;
    solid.world_from_local = primitive.rotation();
    solid.center = primitive.center;
    solid.shape = primitive.shape;
    solid.half_size = primitive.size / 2.0;
    solid.bounding_radius = solid.half_size.norm();
    solids_.push_back(solid);
  }
}

std::optional<RayHit> RayCaster::cast(const Eigen::Vector3d& origin,
                                      const Eigen::Vector3d& direction, double max_distance) const {
  std::optional<RayHit> nearest;
  double best = max_distance;
  for (std::size_t i = 0; i < solids_.size(); ++i) {
    const Solid& solid = solids_[i];
    // Cheap rejection with the bounding sphere.
    const Eigen::Vector3d to_center = solid.center - origin;
    const double along = to_center.dot(direction);
    const double miss_squared = to_center.squaredNorm() - along * along;
    if (miss_squared > solid.bounding_radius * solid.bounding_radius) continue;
    if (along + solid.bounding_radius < 0.0 || along - solid.bounding_radius > best) continue;

    const Eigen::Vector3d local_origin =
        solid.world_from_local.transpose() * (origin - solid.center);
    const Eigen::Vector3d local_direction = solid.world_from_local.transpose() * direction;
    const auto hit = solid.shape == Shape::kBox
                         ? hitBox(local_origin, local_direction, solid.half_size)
                         : hitCylinder(local_origin, local_direction, solid.half_size);
    if (!hit || hit->first >= best) continue;
    best = hit->first;
    Eigen::Vector3d local_normal = Eigen::Vector3d::Zero();
    if (solid.shape == Shape::kBox) {
      local_normal[hit->second / 2] = (hit->second % 2 == 0) ? -1.0 : 1.0;
    } else if (hit->second == 0) {
      const Eigen::Vector3d p = local_origin + best * local_direction;
      local_normal = Eigen::Vector3d(p.x(), p.y(), 0.0).normalized();
    } else {
      local_normal.z() = hit->second == 1 ? -1.0 : 1.0;
    }
    nearest = RayHit{best, int(i), hit->second, solid.world_from_local * local_normal};
  }
  return nearest;
}

}  // namespace clearway::sim
