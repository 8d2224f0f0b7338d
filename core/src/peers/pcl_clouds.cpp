#include "pcl_clouds.h"

#include <pcl/common/centroid.h>

#include <Eigen/Eigenvalues>
#include <limits>

namespace clearway::peers::detail {

pcl::PointCloud<pcl::PointXYZ>::Ptr organisedCloud(const Scan& scan) {
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>(std::uint32_t(scan.pointsPerLine()),
                                                                std::uint32_t(scan.lines.size()));
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const Point3f& p = scan.points[i];
    (*cloud)[i] = scan.isValid(i) ? pcl::PointXYZ(p.x, p.y, p.z) : pcl::PointXYZ(kNaN, kNaN, kNaN);
  }
  cloud->is_dense = false;
  return cloud;
}

pcl::PointCloud<pcl::PointXYZ>::Ptr validCloud(const Scan& scan,
                                               std::vector<std::uint32_t>& scan_index) {
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->reserve(scan.size());
  scan_index.clear();
  scan_index.reserve(scan.size());
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!scan.isValid(i)) continue;
    const Point3f& p = scan.points[i];
    cloud->push_back(pcl::PointXYZ(p.x, p.y, p.z));
    scan_index.push_back(std::uint32_t(i));
  }
  return cloud;
}

void addPlane(const pcl::PointCloud<pcl::PointXYZ>& cloud, const pcl::Indices& indices,
              const std::vector<std::uint32_t>& scan_index, eval::PointPlanes& result) {
  if (indices.size() < 3) return;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  Eigen::Vector4d centroid = Eigen::Vector4d::Zero();
  if (pcl::computeMeanAndCovarianceMatrix(cloud, indices, covariance, centroid) < 3) return;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  eval::ResultPlane plane;
  plane.normal = solver.eigenvectors().col(0).normalized();  // smallest eigenvalue
  plane.offset = plane.normal.dot(centroid.head<3>());
  if (plane.offset < 0) {
    plane.normal = -plane.normal;
    plane.offset = -plane.offset;
  }
  plane.kind = "other";
  const auto label = std::int32_t(result.planes.size());
  result.planes.push_back(plane);
  for (const pcl::index_t index : indices) {
    const std::size_t scan_point =
        scan_index.empty() ? std::size_t(index) : scan_index[std::size_t(index)];
    result.point_plane[scan_point] = label;
  }
}

eval::PointPlanes noPlanes(const Scan& scan) {
  eval::PointPlanes result;
  result.point_plane.assign(scan.size(), -1);
  return result;
}

}  // namespace clearway::peers::detail
