#include "clearway/ui/floor_pick.h"

#include <Eigen/Eigenvalues>
#include <limits>

namespace clearway::ui {
namespace {

Eigen::Vector3d positionOf(const Scan& scan, std::size_t i) {
  const Point3f& p = scan.points[i];
  return {p.x, p.y, p.z};
}

// Turned so the scanner (the frame's origin) lies on its positive side: from the floor up.
Eigen::Vector3d towardsScanner(Eigen::Vector3d normal, const Eigen::Vector3d& on_plane) {
  if (normal.dot(-on_plane) < 0) normal = -normal;
  return normal.normalized();
}

}  // namespace

FloorPick floorUpAt(const Scan& scan, const ScanAnalysis& analysis,
                    const Eigen::Vector3d& scanner_point) {
  FloorPick pick;
  std::size_t nearest = std::numeric_limits<std::size_t>::max();
  double nearest_distance = kFloorPickReach;
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    if (!scan.isValid(i)) continue;
    const double distance = (positionOf(scan, i) - scanner_point).norm();
    if (distance < nearest_distance) {
      nearest_distance = distance;
      nearest = i;
    }
  }
  if (nearest == std::numeric_limits<std::size_t>::max()) {
    pick.reason = "no measured point near the picked place: pick on the floor's points";
    return pick;
  }
  const Eigen::Vector3d hit = positionOf(scan, nearest);

  const auto& point_plane = analysis.planes.point_plane;
  if (nearest < point_plane.size() && point_plane[nearest] >= 0) {
    const auto plane_index = std::size_t(point_plane[nearest]);
    const Plane& plane = analysis.planes.planes[plane_index];
    pick.up = towardsScanner(plane.normal, hit);
    pick.how = "plane " + std::to_string(plane_index) + " (" +
               std::to_string(plane.support_points) + " points)";
    return pick;
  }

  // No validated plane there: fit the neighbourhood.
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
  int count = 0;
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    if (!scan.isValid(i)) continue;
    const Eigen::Vector3d p = positionOf(scan, i);
    if ((p - hit).norm() > kFloorFitRadius) continue;
    sum += p;
    outer += p * p.transpose();
    ++count;
  }
  if (count < kFloorFitMinPoints) {
    pick.reason = "too few points around the picked place (" + std::to_string(count) +
                  ") to tell its plane: pick where the floor is densely measured";
    return pick;
  }
  const Eigen::Vector3d mean = sum / count;
  const Eigen::Matrix3d covariance = outer / count - mean * mean.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  const Eigen::Vector3d spread = solver.eigenvalues();  // ascending
  if (spread[0] > kFloorFlatness * spread[1]) {
    pick.reason = "the picked place is not flat: pick the open floor";
    return pick;
  }
  pick.up = towardsScanner(solver.eigenvectors().col(0), mean);
  pick.how = "fitted to " + std::to_string(count) + " nearby points";
  return pick;
}

}  // namespace clearway::ui
