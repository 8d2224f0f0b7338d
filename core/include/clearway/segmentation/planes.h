#pragma once

// Stages 2 and 3 (paper II-B, II-C): similar segments of neighbouring scan lines are clustered into
// planes; each plane is then validated on a support image, and points are assigned to planes.

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "clearway/point_class.h"
#include "clearway/progress.h"
#include "clearway/scan.h"
#include "clearway/segmentation/line_segments.h"
#include "clearway/segmentation/params.h"

namespace clearway {
namespace detail {
struct RingLayout;  // src/segmentation/ring_support.h
}  // namespace detail

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

// What the clustering needs to know of the sensor (from describeSensor(), sensor_geometry.h).
struct LineNeighbourhood {
  // The last line neighbours the first (a full turn of the turntable); otherwise lines are
  // neighbours only within the file's order (a partial turn, multi-beam rings).
  bool closed_turn = true;
  // Multi-beam: the elevation step between rings [rad], 0 otherwise. Neighbouring rings meet the
  // ground range^2 / height x step apart (1.6 m at 20 m for a Velodyne 1.7 m up), so similar
  // segments below the sensor may lie that far apart.
  double ring_step = 0.0;
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  // gravity's up in the scan's frame
};

// `threads`: the search for similar segments of neighbouring lines is shared out; the planes are
// the same for any number.
std::vector<Plane> clusterSegments(const std::vector<LineSegment>& segments, std::size_t line_count,
                                   const ClusterParams& params,
                                   const LineNeighbourhood& neighbourhood = {}, int threads = 1);

// Support image of one plane: which cells of its 2D grid hold a connected supported area.
struct SupportImage {
  Eigen::Vector3d u_axis, v_axis;  // in-plane basis
  double u0 = 0.0, v0 = 0.0, cell = 0.2;
  int width = 0, height = 0;
  std::vector<std::uint8_t> kept;  // 1 where the cell belongs to a large enough supported area
  bool contains(const Eigen::Vector3d& p) const;
};

// A candidate plane the support test removed, as measured: the no-ground reason names a floor
// that was seen but failed validation instead of saying the floor is out of view.
struct RejectedPlane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0.0;
  std::size_t support_points = 0;
  double support_area = 0.0;    // [m^2]
  double inner_fraction = 0.0;  // share of support in the inner half of the band
};

struct ValidatedPlanes {
  std::vector<Plane> planes;              // the validated ones only
  std::vector<SupportImage> supports;     // one per plane
  std::vector<std::int32_t> point_plane;  // per scan point: plane index or -1
  std::size_t rejected = 0;               // candidate planes the support test removed
  std::vector<RejectedPlane> rejected_planes;
  // The limits they were held to (ValidationParams::min_area, min_inner_fraction).
  double min_area = 0.0, min_inner_fraction = 0.0;
};

// What validation needs to know of the sensor: how far apart its lines may lie on a plane, and
// how its range noise grows.
struct SensorSpread {
  // A large plane's area extends over gaps between its scan lines up to this wide [m] (a
  // multi-beam sensor's far rings on the ground lie much farther apart than a RoSi's lines).
  double growth_gap = 0.4;
  // The support band widens by this much per metre of range (0: params.support_distance flat).
  double support_per_metre = 0.0;
  // Crowding (the inner-fraction test) is judged about the local surface, each support cell's mean
  // distance to the plane, not about the plane itself: a multi-beam sensor's plane spans tens of
  // metres of road whose camber and slope changes move it by more than the band's inner half,
  // while its rings resolve the surface locally (docs/ALGORITHM.md, "Multi-beam frames").
  bool local_crowding = false;
  // When given (the segments the planes were clustered from), a plane's area stays within
  // growth_gap of its own segments: a plane fitted to a few multi-beam rings has a tilt known only
  // to their noise, and far from them it cuts the cars and kerbs it meets.
  const std::vector<LineSegment>* own_segments = nullptr;
  // A multi-beam frame's rings (indices into scan.lines, lowest elevation first) and the azimuth
  // step along them [rad]: where two neighbouring rings both support a plane at the same azimuth,
  // the cells between them are supported too (src/segmentation/ring_support.h). Empty otherwise.
  std::vector<std::size_t> rings_by_elevation;
  double ring_azimuth_step = 0.0;
  // Each return's facing return on the next ring up (src/segmentation/ring_support.h), when the
  // caller worked it out for later stages too; null: validation works it out.
  std::shared_ptr<const detail::RingLayout> ring_layout;
};

ValidatedPlanes validatePlanes(const Scan& scan, std::vector<Plane> candidates,
                               const ValidationParams& params, int threads = 2,
                               const SensorSpread& spread = {});

}  // namespace clearway
