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

eval::PointPlanes pclOrganizedMultiPlane(const Scan& scan, int /*threads: PCL's is serial*/,
                                         const PlanePeerSettings& settings) {
  eval::PointPlanes result = detail::noPlanes(scan);
  if (!scan.isOrganised()) return result;
  const auto cloud = detail::organisedCloud(scan);

  pcl::IntegralImageNormalEstimation<pcl::PointXYZ, pcl::Normal> normal_estimation;
  normal_estimation.setNormalEstimationMethod(normal_estimation.AVERAGE_3D_GRADIENT);
  normal_estimation.setMaxDepthChangeFactor(settings.depth_change_factor);
  normal_estimation.setNormalSmoothingSize(settings.normal_smoothing_size);
  normal_estimation.setInputCloud(cloud);
  auto normals = std::make_shared<pcl::PointCloud<pcl::Normal>>();
  normal_estimation.compute(*normals);

  pcl::OrganizedMultiPlaneSegmentation<pcl::PointXYZ, pcl::Normal, pcl::Label> segmentation;
  segmentation.setMinInliers(unsigned(settings.min_plane_points));
  segmentation.setAngularThreshold(settings.angle_threshold_deg * std::numbers::pi / 180.0);
  segmentation.setDistanceThreshold(settings.distance_threshold);
  segmentation.setInputNormals(normals);
  segmentation.setInputCloud(cloud);
  std::vector<pcl::PlanarRegion<pcl::PointXYZ>,
              Eigen::aligned_allocator<pcl::PlanarRegion<pcl::PointXYZ>>>
      regions;
  std::vector<pcl::ModelCoefficients> coefficients;
  std::vector<pcl::PointIndices> inliers, label_indices, boundaries;
  auto labels = std::make_shared<pcl::PointCloud<pcl::Label>>();
  segmentation.segmentAndRefine(regions, coefficients, inliers, labels, label_indices, boundaries);
  for (const pcl::PointIndices& plane : inliers)
    detail::addPlane(*cloud, plane.indices, {}, result);
  return result;
}

}  // namespace clearway::peers
