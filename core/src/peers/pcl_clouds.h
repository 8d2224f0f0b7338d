#pragma once

// Scan -> PCL clouds for the plane peers, and their results back into per-point planes. Included
// only by the peers' .cpp files: it brings in PCL's headers.

#include <pcl/PointIndices.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <vector>

#include "clearway/eval/segmentation_accuracy.h"
#include "clearway/scan.h"

namespace clearway::peers::detail {

// One row per scan line, NaN where a point is not valid. Requires scan.isOrganised().
pcl::PointCloud<pcl::PointXYZ>::Ptr organisedCloud(const Scan& scan);

// The valid points only; scan_index[i] is the scan index of cloud point i.
pcl::PointCloud<pcl::PointXYZ>::Ptr validCloud(const Scan& scan,
                                               std::vector<std::uint32_t>& scan_index);

// Adds one plane with its points (indices into the cloud; scan_index maps them to the scan, or
// is empty when the cloud is the scan itself). The plane is the least-squares fit of its points.
void addPlane(const pcl::PointCloud<pcl::PointXYZ>& cloud, const pcl::Indices& indices,
              const std::vector<std::uint32_t>& scan_index, eval::PointPlanes& result);

// Empty result for a scan: no planes, every point unassigned.
eval::PointPlanes noPlanes(const Scan& scan);

}  // namespace clearway::peers::detail
