// PCL's region growing on k-nearest-neighbour normals: works on any cloud, organised or not.

#include <pcl/features/normal_3d_omp.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/region_growing.h>

#include <numbers>

#include "clearway/peers/plane_peers.h"
#include "pcl_clouds.h"

namespace clearway::peers {

eval::PointPlanes pclRegionGrowing(const Scan& scan, int threads,
                                   const PlanePeerSettings& settings) {
  eval::PointPlanes result = detail::noPlanes(scan);
  std::vector<std::uint32_t> scan_index;
  const auto cloud = detail::validCloud(scan, scan_index);
  if (cloud->size() < 3) return result;

  auto tree = std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>();
  pcl::NormalEstimationOMP<pcl::PointXYZ, pcl::Normal> normal_estimation{unsigned(threads)};
  normal_estimation.setSearchMethod(tree);
  normal_estimation.setKSearch(settings.neighbours);
  normal_estimation.setInputCloud(cloud);
  auto normals = std::make_shared<pcl::PointCloud<pcl::Normal>>();
  normal_estimation.compute(*normals);

  pcl::RegionGrowing<pcl::PointXYZ, pcl::Normal> region_growing;
  region_growing.setMinClusterSize(pcl::uindex_t(settings.min_plane_points));
  region_growing.setSearchMethod(tree);
  region_growing.setNumberOfNeighbours(unsigned(settings.neighbours));
  region_growing.setSmoothnessThreshold(
      float(settings.angle_threshold_deg * std::numbers::pi / 180.0));
  region_growing.setCurvatureThreshold(settings.max_curvature);
  region_growing.setInputCloud(cloud);
  region_growing.setInputNormals(normals);
  std::vector<pcl::PointIndices> regions;
  region_growing.extract(regions);
  for (const pcl::PointIndices& region : regions)
    detail::addPlane(*cloud, region.indices, scan_index, result);
  return result;
}

}  // namespace clearway::peers
