// PCL's organised multi-plane segmentation, the fastest general plane finder for organised
// clouds: integral-image normals, then connected components of points with similar normals and
// plane distance.

#include <pcl/features/integral_image_normal.h>
#include <pcl/segmentation/organized_multi_plane_segmentation.h>

#include <cmath>
#include <numbers>

#include "clearway/peers/plane_peers.h"
#include "pcl_clouds.h"

namespace clearway::peers {

eval::PointPlanes pclOrganizedMultiPlane(const Scan& scan, int /*threads: PCL's is serial*/) {
  eval::PointPlanes result = detail::noPlanes(scan);
  if (!scan.isOrganised()) return result;
  const auto cloud = detail::organisedCloud(scan);

  pcl::IntegralImageNormalEstimation<pcl::PointXYZ, pcl::Normal> normal_estimation;
  normal_estimation.setNormalEstimationMethod(normal_estimation.AVERAGE_3D_GRADIENT);
  // Our z is the turntable axis, not a camera's depth: PCL's depth-change test compares z of
  // neighbours, so it is set loose enough (10 cm at z = 0) not to cut planes at every row.
  normal_estimation.setMaxDepthChangeFactor(0.05F);
  normal_estimation.setNormalSmoothingSize(10.0F);
  normal_estimation.setInputCloud(cloud);
  auto normals = std::make_shared<pcl::PointCloud<pcl::Normal>>();
  normal_estimation.compute(*normals);

  pcl::OrganizedMultiPlaneSegmentation<pcl::PointXYZ, pcl::Normal, pcl::Label> segmentation;
  segmentation.setMinInliers(200);
  segmentation.setAngularThreshold(3.0 * std::numbers::pi / 180.0);
  segmentation.setDistanceThreshold(0.03);
  segmentation.setInputNormals(normals);
  segmentation.setInputCloud(cloud);
  std::vector<pcl::ModelCoefficients> coefficients;
  std::vector<pcl::PointIndices> inliers;
  segmentation.segment(coefficients, inliers);
  for (const pcl::PointIndices& plane : inliers)
    detail::addPlane(*cloud, plane.indices, {}, result);
  return result;
}

}  // namespace clearway::peers
