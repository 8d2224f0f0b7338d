#include "ring_ground.h"

#include <Eigen/Core>
#include <cmath>

#include "ring_support.h"

namespace clearway::detail {

std::size_t followGroundOutward(const Scan& scan,
                                const std::vector<std::size_t>& rings_by_elevation,
                                const RingLayout& layout, const std::vector<Plane>& planes,
                                const std::vector<int>& ground, const OutwardGroundLimits& limits,
                                std::vector<std::int32_t>& point_plane) {
  // Facing returns however far apart: the far rings of a sparse head are what this is for.
  if (ground.empty() || rings_by_elevation.size() < 2 || layout.empty()) return 0;
  std::vector<bool> is_ground(planes.size(), false);
  for (const int g : ground)
    is_ground[std::size_t(g)] = true;
  auto at = [&](std::size_t i) {
    const Point3f& p = scan.points[i];
    return Eigen::Vector3d(p.x, p.y, p.z);
  };
  std::size_t joined = 0;
  // Ring by ring up, so that a return joined on one ring carries the ground on to the next.
  for (const std::size_t line : rings_by_elevation) {
    const ScanLine& ring = scan.lines[line];
    for (std::size_t i = ring.first; i < ring.first + ring.count; ++i) {
      const std::int32_t g = point_plane[i];
      if (g < 0 || !is_ground[std::size_t(g)] || !scan.isValid(i)) continue;
      const std::uint32_t next = layout.facing[i];
      if (next == RingLayout::kNone || point_plane[next] >= 0) continue;
      const Plane& plane = planes[std::size_t(g)];
      const Eigen::Vector3d from = at(i), to = at(next);
      if (std::abs(plane.signedDistance(to)) > limits.off_plane + limits.per_metre * to.norm())
        continue;
      const Eigen::Vector3d step = to - from;
      const double rise = plane.normal.dot(step);
      const double run = (step - rise * plane.normal).norm();
      if (std::abs(rise) > run * limits.max_slope + limits.noise) continue;
      point_plane[next] = g;
      ++joined;
    }
  }
  return joined;
}

}  // namespace clearway::detail
