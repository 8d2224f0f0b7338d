// The most common recipe for "all the planes in a cloud": PCL's RANSAC plane fit, run again on
// what is left until no plane with enough points remains.

#include <pcl/ModelCoefficients.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/segmentation/sac_segmentation.h>

#include "clearway/peers/plane_peers.h"
#include "pcl_clouds.h"

namespace clearway::peers {

eval::PointPlanes pclRansacPlanes(const Scan& scan, int threads,
                                  const PlanePeerSettings& settings) {
  eval::PointPlanes result = detail::noPlanes(scan);
  std::vector<std::uint32_t> scan_index;
  const auto cloud = detail::validCloud(scan, scan_index);

  pcl::SACSegmentation<pcl::PointXYZ> segmentation;
  segmentation.setModelType(pcl::SACMODEL_PLANE);
  segmentation.setMethodType(pcl::SAC_RANSAC);
  segmentation.setDistanceThreshold(settings.distance_threshold);
  segmentation.setMaxIterations(settings.ransac_iterations);
  segmentation.setOptimizeCoefficients(false);  // addPlane refits on the inliers
  segmentation.setNumberOfThreads(threads);
  segmentation.setInputCloud(cloud);

  auto remaining = std::make_shared<pcl::Indices>(cloud->size());
  for (std::size_t i = 0; i < remaining->size(); ++i)
    (*remaining)[i] = pcl::index_t(i);
  std::vector<bool> taken(cloud->size(), false);
  for (int plane = 0; plane < settings.max_planes && remaining->size() >= settings.min_plane_points;
       ++plane) {
    segmentation.setIndices(remaining);
    pcl::PointIndices inliers;
    pcl::ModelCoefficients coefficients;
    segmentation.segment(inliers, coefficients);
    if (inliers.indices.size() < settings.min_plane_points) break;
    detail::addPlane(*cloud, inliers.indices, scan_index, result);
    for (const pcl::index_t index : inliers.indices)
      taken[std::size_t(index)] = true;
    auto rest = std::make_shared<pcl::Indices>();
    rest->reserve(remaining->size() - inliers.indices.size());
    for (const pcl::index_t index : *remaining)
      if (!taken[std::size_t(index)]) rest->push_back(index);
    remaining = rest;
  }
  return result;
}

}  // namespace clearway::peers
