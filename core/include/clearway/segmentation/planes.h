#pragma once

// Stages 2 and 3 (paper II-B, II-C): similar segments of neighbouring scan lines are clustered into
// planes; each plane is then validated on a support image, and points are assigned to planes.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "clearway/point_class.h"
#include "clearway/progress.h"
#include "clearway/scan.h"
#include "clearway/segmentation/line_segments.h"
#include "clearway/segmentation/params.h"

namespace clearway {

enum class PlaneKind : std::uint8_t { kUnknown, kGround, kWall, kCeiling, kOther };
const char* planeKindName(PlaneKind kind);

// A plane n . p = offset in the scanner frame, with n unit length and offset >= 0 (n points from
// the sensor towards the plane, so offset is the sensor's distance to it).
struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0.0;
  std::vector<std::uint32_t> segments;  // indices into the segment list
  PointMoments moments;                 // of the segments' points
  double rms = 0.0;                     // residual of the least-squares fit [m]

  // Filled by validation:
  bool validated = false;
  std::size_t support_points = 0;
  double support_area = 0.0;    // largest connected supported area [m^2]
  double inner_fraction = 0.0;  // share of support in the inner half of the band
  PlaneKind kind = PlaneKind::kUnknown;

  double signedDistance(const Eigen::Vector3d& p) const { return normal.dot(p) - offset; }
};

// Least-squares plane of a moment set; normal oriented so offset >= 0.
Plane fitPlane(const PointMoments& moments);

std::vector<Plane> clusterSegments(const std::vector<LineSegment>& segments, std::size_t line_count,
                                   const ClusterParams& params);

// Support image of one plane: which cells of its 2D grid hold a connected supported area.
struct SupportImage {
  Eigen::Vector3d u_axis, v_axis;  // in-plane basis
  double u0 = 0.0, v0 = 0.0, cell = 0.2;
  int width = 0, height = 0;
  std::vector<std::uint8_t> kept;  // 1 where the cell belongs to a large enough supported area
  bool contains(const Eigen::Vector3d& p) const;
};

struct ValidatedPlanes {
  std::vector<Plane> planes;              // the validated ones only
  std::vector<SupportImage> supports;     // one per plane
  std::vector<std::int32_t> point_plane;  // per scan point: plane index or -1
  std::size_t rejected = 0;               // candidate planes the support test removed
};

ValidatedPlanes validatePlanes(const Scan& scan, std::vector<Plane> candidates,
                               const ValidationParams& params, int threads = 2);

}  // namespace clearway
