#include "clearway/sim/scene.h"

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <numeric>

namespace clearway::sim {

Eigen::Matrix3d Primitive::rotation() const {
  const double to_rad = std::numbers::pi / 180.0;
  return (Eigen::AngleAxisd(yaw_deg * to_rad, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(pitch_deg * to_rad, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll_deg * to_rad, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

bool Primitive::holdsInside(const Eigen::Vector3d& point) const {
  const Eigen::Vector3d local = rotation().transpose() * (point - center);
  const Eigen::Vector3d half = size / 2;
  if (shape == Shape::kCylinder)
    return std::abs(local.z()) < half.z() && local.head<2>().norm() < half.x();
  return (local.cwiseAbs() - half).maxCoeff() < 0.0;
}

std::vector<std::pair<std::string, std::string>> reachablePlaces(const Scene& scene,
                                                                 const RobotBox& robot) {
  const std::size_t n = scene.places.size();
  std::vector<std::size_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](std::size_t i) {
    while (parent[i] != i)
      i = parent[i] = parent[parent[i]];
    return i;
  };
  auto index = [&](const std::string& name) {
    for (std::size_t i = 0; i < n; ++i)
      if (scene.places[i].name == name) return i;
    return n;
  };
  for (const Passage& passage : scene.passages) {
    const bool wide_enough = passage.width <= 0.0 || robot.width < passage.width;
    const bool high_enough = passage.height <= 0.0 || robot.height < passage.height;
    const bool climbable = passage.step <= robot.max_step;
    const std::size_t a = index(passage.from), b = index(passage.to);
    if (a < n && b < n && wide_enough && high_enough && climbable) parent[root(a)] = root(b);
  }
  std::vector<std::pair<std::string, std::string>> pairs;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      if (root(i) == root(j)) pairs.emplace_back(scene.places[i].name, scene.places[j].name);
  return pairs;
}

}  // namespace clearway::sim
