// Stage 4 (paper II-D): ground planes are planes no steeper than the robot can drive, with the
// scanner above them (which removes ceilings). The one with the largest supported area is the
// reference: the traversability map lies on it.

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "clearway/segmentation/scan_analysis.h"
#include "parallel.h"

namespace clearway {

Eigen::Vector3d upDirection(const Scan& scan) {
  if (!scan.sensor_pose) return Eigen::Vector3d::UnitZ();
  const auto& r = scan.sensor_pose->rotation;
  // Row 2 of world_from_scanner is world z expressed in the scanner frame.
  return Eigen::Vector3d(r[6], r[7], r[8]).normalized();
}

namespace {

// What a plane is to a robot under gravity's `up`: ground (no steeper than it drives, the scanner
// above it), a ceiling (as flat, the scanner below it) or a wall.
PlaneKind kindOf(const Eigen::Vector3d& normal, double offset, const Eigen::Vector3d& up,
                 const GroundParams& params) {
  const double facing = normal.dot(up);
  const double scanner_height = facing < 0 ? offset : -offset;
  if (std::abs(facing) < std::cos(params.max_slope_deg * std::numbers::pi / 180.0))
    return PlaneKind::kWall;
  if (scanner_height < params.min_scanner_height) return PlaneKind::kCeiling;
  return PlaneKind::kGround;
}

// Of the candidates validation removed, the floor with the most supporting points, if any.
const RejectedPlane* rejectedFloor(const ScanAnalysis& analysis, const GroundParams& params) {
  const RejectedPlane* floor = nullptr;
  for (const RejectedPlane& plane : analysis.planes.rejected_planes)
    if (kindOf(plane.normal, plane.offset, analysis.up, params) == PlaneKind::kGround &&
        (!floor || plane.support_points > floor->support_points))
      floor = &plane;
  return floor;
}

std::string fixed(double value, int decimals) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(decimals) << value;
  return text.str();
}

// A floor was seen but the support test removed it: which limits it failed, measured.
std::string rejectedFloorReason(const RejectedPlane& floor, const ValidatedPlanes& planes,
                                const std::string& slope) {
  std::string why;
  if (floor.inner_fraction < planes.min_inner_fraction)
    why = "its points do not lie on one flat surface (inner fraction " +
          fixed(floor.inner_fraction, 2) + ", at least " + fixed(planes.min_inner_fraction, 2) +
          " needed: uneven, cluttered or stepped ground fitted as one plane)";
  if (floor.support_area < planes.min_area)
    why += std::string(why.empty() ? "" : "; ") + "its largest connected supported area is " +
           fixed(floor.support_area, 2) + " m2, at least " + fixed(planes.min_area, 2) +
           " m2 needed (too little of it seen)";
  return "no ground plane found: a floor candidate was seen (" +
         std::to_string(floor.support_points) + " points on a plane flatter than " + slope +
         " below the scanner) but failed plane validation: " + why +
         "; move the robot or the arm so that more of the floor is in view and scan again";
}

}  // namespace

// Why no ground was found, from what the earlier stages saw: the cause, then what to do.
std::string noGroundReason(const ScanAnalysis& analysis, const GroundParams& params,
                           bool up_known) {
  const std::string slope = std::to_string(int(params.max_slope_deg)) + " deg";
  if (analysis.sensor.lines < 2)
    return "no ground plane found: the scan has one scan line, and planes need neighbouring "
           "lines (a multi-beam frame? give its rings with --rings N)";
  if (up_known)
    if (const RejectedPlane* floor = rejectedFloor(analysis, params))
      return rejectedFloorReason(*floor, analysis.planes, slope);
  if (analysis.planes.planes.empty())
    return "no ground plane found: no plane in the scan (" +
           std::to_string(analysis.segments.size()) + " line segments, " +
           std::to_string(analysis.candidate_planes) +
           " candidate planes, none with enough supported area: too few points on any surface?)";
  bool flat_above = false;
  for (const Plane& plane : analysis.planes.planes)
    flat_above = flat_above || plane.kind == PlaneKind::kCeiling;
  if (flat_above)
    return "no ground plane found: the only planes flatter than " + slope +
           " are above the scanner (a ceiling); the floor is out of view (point the scanner "
           "down or move the arm and scan again)";
  return "no ground plane found: no plane flatter than " + slope + " (" +
         std::to_string(analysis.planes.planes.size()) +
         " planes, all walls; is the floor out of view? move the robot or the arm and scan again)";
}

void selectGround(ScanAnalysis& analysis, const GroundParams& params) {
  analysis.ground_planes.clear();
  analysis.reference_ground = -1;
  // The reference is the largest ground plane: by its supported area, or for a multi-beam frame
  // by its supporting returns. A multi-beam plane's area depends on how far away its rings lie
  // (sparse rings are joined across their gaps, ring_support.h): a patch of far road, tilted a
  // little against the road under the car, covered twice the area of that road from a seventh of
  // its returns on KITTI 000001, and sat 0.55 m below the car. Returns thin out with range.
  const bool by_returns = analysis.sensor.kind == SensorKind::kMultiBeam;
  double best = 0.0;
  for (std::size_t k = 0; k < analysis.planes.planes.size(); ++k) {
    Plane& plane = analysis.planes.planes[k];
    plane.kind = kindOf(plane.normal, plane.offset, analysis.up, params);
    if (plane.kind == PlaneKind::kGround) {
      analysis.ground_planes.push_back(int(k));
      const double size = by_returns ? double(plane.support_points) : plane.support_area;
      if (size > best) {
        best = size;
        analysis.reference_ground = int(k);
      }
    }
  }
  analysis.ground_found = analysis.reference_ground >= 0;
  if (!analysis.ground_found) {
    analysis.reason = noGroundReason(analysis, params);
    return;
  }
  std::stable_partition(analysis.ground_planes.begin(), analysis.ground_planes.end(),
                        [&](int k) { return k == analysis.reference_ground; });

  // Map frame: on the reference plane under the scanner, z along the plane's upward normal,
  // x along the scanner's x axis (or y, if x is nearly vertical) projected onto the plane.
  const Plane& reference = analysis.planes.planes[std::size_t(analysis.reference_ground)];
  const Eigen::Vector3d z =
      reference.normal.dot(analysis.up) < 0 ? -reference.normal : reference.normal;
  Eigen::Vector3d x = Eigen::Vector3d::UnitX() - z.x() * z;
  if (x.norm() < 0.3) x = Eigen::Vector3d::UnitY() - z.y() * z;
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d
      rotation;  // map_from_scanner rotation: rows are the map axes in the scanner frame
  rotation.row(0) = x.transpose();
  rotation.row(1) = y.transpose();
  rotation.row(2) = z.transpose();
  // The scanner sits at map (0, 0, height): the map origin is its foot on the reference plane.
  const double scanner_height =
      reference.normal.dot(analysis.up) < 0 ? reference.offset : -reference.offset;
  analysis.map_from_scanner = Eigen::Isometry3d::Identity();
  analysis.map_from_scanner.linear() = rotation;
  analysis.map_from_scanner.translation() = Eigen::Vector3d(0.0, 0.0, scanner_height);

  // Each plane as a height over the map: n . p = d in the map frame gives z = (d - nx x - ny y) /
  // nz.
  analysis.height_coefficients.assign(analysis.planes.planes.size(), Eigen::Vector3d::Zero());
  for (std::size_t k = 0; k < analysis.planes.planes.size(); ++k) {
    const Plane& p = analysis.planes.planes[k];
    const Eigen::Vector3d n = rotation * p.normal;
    if (std::abs(n.z()) < 1e-6) continue;  // a wall has no height over the map
    const double d = p.offset + n.dot(analysis.map_from_scanner.translation());
    analysis.height_coefficients[k] = Eigen::Vector3d(d, -n.x(), -n.y()) / n.z();
  }
}

std::size_t absorbGroundPatches(const Scan& scan, const ValidationParams& validation,
                                const SensorSpread& spread, ScanAnalysis& analysis) {
  if (!analysis.ground_found || analysis.ground_planes.size() < 2) return 0;
  const int reference = analysis.reference_ground;
  const Plane& reference_plane = analysis.planes.planes[std::size_t(reference)];
  const SupportImage& reference_area = analysis.planes.supports[std::size_t(reference)];
  std::vector<std::int32_t>& point_plane = analysis.planes.point_plane;
  std::vector<bool> is_other_ground(analysis.planes.planes.size(), false);
  for (const int g : analysis.ground_planes)
    is_other_ground[std::size_t(g)] = g != reference;
  // Per point of another ground plane: does the reference support it (band and area)?
  auto onReference = [&](std::size_t i) {
    const Point3f& p = scan.points[i];
    const Eigen::Vector3d q(p.x, p.y, p.z);
    const double band = validation.support_distance + spread.support_per_metre * q.norm();
    return std::abs(reference_plane.signedDistance(q)) <= band && reference_area.contains(q);
  };
  // Judged on the plane's own segments, the points it was fitted to (not the support it claims).
  std::vector<bool> absorbed(analysis.planes.planes.size(), false);
  std::size_t count = 0;
  for (std::size_t k = 0; k < absorbed.size(); ++k) {
    if (!is_other_ground[k]) continue;
    std::size_t points = 0, on_reference = 0;
    for (const std::uint32_t s : analysis.planes.planes[k].segments) {
      const LineSegment& segment = analysis.segments[s];
      for (std::size_t i = segment.first; i <= segment.last; ++i) {
        if (!scan.isValid(i)) continue;
        ++points;
        on_reference += onReference(i);
      }
    }
    absorbed[k] = 2 * on_reference > points;
    if (!absorbed[k]) continue;
    analysis.planes.planes[k].kind = PlaneKind::kOther;
    ++count;
  }
  if (count == 0) return 0;
  for (std::size_t i = 0; i < point_plane.size(); ++i) {
    const int k = point_plane[i];
    if (k >= 0 && absorbed[std::size_t(k)]) point_plane[i] = onReference(i) ? reference : -1;
  }
  std::erase_if(analysis.ground_planes, [&](int g) { return absorbed[std::size_t(g)]; });
  return count;
}

std::size_t dropUnreachableGround(const Scan& scan, double max_rise, double min_width,
                                  ScanAnalysis& analysis) {
  if (!analysis.ground_found || analysis.ground_planes.size() < 2) return 0;
  const std::vector<Plane>& planes = analysis.planes.planes;
  // Whether `from`'s own points come within a riser of `to`, over `to`'s area, along at least
  // min_width of its lines (consecutive such points, summed over its segments).
  auto reaches = [&](int from, int to) {
    const Plane& target = planes[std::size_t(to)];
    const SupportImage& area = analysis.planes.supports[std::size_t(to)];
    double seam = 0.0;
    for (const std::uint32_t s : planes[std::size_t(from)].segments) {
      const LineSegment& segment = analysis.segments[s];
      bool previous_meets = false;
      Eigen::Vector3d previous = Eigen::Vector3d::Zero();
      for (std::size_t i = segment.first; i <= segment.last; ++i) {
        if (!scan.isValid(i)) continue;
        const Point3f& p = scan.points[i];
        const Eigen::Vector3d q(p.x, p.y, p.z);
        const bool meets = std::abs(target.signedDistance(q)) <= max_rise && area.contains(q);
        if (meets && previous_meets) seam += (q - previous).norm();
        if (seam >= min_width) return true;
        previous_meets = meets;
        previous = q;
      }
    }
    return false;
  };
  std::vector<int> kept = {analysis.reference_ground};
  std::vector<int> waiting(analysis.ground_planes.begin() + 1, analysis.ground_planes.end());
  for (std::size_t next = 0; next < kept.size(); ++next) {
    const int from = kept[next];
    std::erase_if(waiting, [&](int g) {
      if (!reaches(g, from)) return false;
      kept.push_back(g);
      return true;
    });
  }
  if (waiting.empty()) return 0;
  std::vector<bool> dropped(planes.size(), false);
  for (const int g : waiting) {
    dropped[std::size_t(g)] = true;
    analysis.planes.planes[std::size_t(g)].kind = PlaneKind::kOther;
  }
  for (std::int32_t& plane : analysis.planes.point_plane)
    if (plane >= 0 && dropped[std::size_t(plane)]) plane = -1;
  std::erase_if(analysis.ground_planes, [&](int g) { return dropped[std::size_t(g)]; });
  return waiting.size();
}

namespace {

// The columns the ground's returns are compared in [m]: a tenth of a metre, far narrower than
// anything the robot drives on and wide enough to hold the returns of several rings on a face;
// wider when the ground spreads so far that such columns would pass kMostColumns.
constexpr double kColumnSize = 0.1;
constexpr double kMostColumns = 1 << 20;

// A ground plane is a surface the robot stands on only if most of its returns lie on top of their
// columns; on a face or over one, the rings see past it.
constexpr double kMostlyOver = 0.5;

}  // namespace

std::size_t dropGroundOverLowerReturns(const Scan& scan, double max_rise, double max_slope_deg,
                                       ScanAnalysis& analysis, int threads) {
  if (!analysis.ground_found) return 0;
  std::vector<std::int32_t>& point_plane = analysis.planes.point_plane;
  const std::vector<Plane>& planes = analysis.planes.planes;
  std::vector<bool> is_ground(planes.size(), false);
  for (const int g : analysis.ground_planes)
    is_ground[std::size_t(g)] = true;
  // In the map frame, z up: only the height and the column matter.
  const Eigen::Matrix3f rotation = analysis.map_from_scanner.linear().cast<float>();
  auto mapped = [&](std::size_t i) {
    const Point3f& p = scan.points[i];
    return Eigen::Vector3f(rotation * Eigen::Vector3f(p.x, p.y, p.z));
  };
  // The ground returns and the columns they span.
  std::vector<std::uint32_t> ground;
  std::vector<Eigen::Vector3f> ground_mapped;
  Eigen::AlignedBox2f box;
  for (std::size_t i = 0; i < point_plane.size(); ++i) {
    if (point_plane[i] < 0 || !is_ground[std::size_t(point_plane[i])] || !scan.isValid(i)) continue;
    ground.push_back(std::uint32_t(i));
    ground_mapped.push_back(mapped(i));
    box.extend(ground_mapped.back().head<2>());
  }
  if (ground.empty()) return 0;
  const Eigen::Vector2d origin = box.min().cast<double>();
  const Eigen::Vector2d sizes = box.sizes().cast<double>();
  const double size = std::max(
      kColumnSize, std::sqrt((sizes.x() + kColumnSize) * (sizes.y() + kColumnSize) / kMostColumns));
  const int columns = int(std::floor(sizes.x() / size)) + 1;
  const int rows = int(std::floor(sizes.y() / size)) + 1;
  // Across a column, ground as steep as the robot drives rises this much: a return lower than a
  // ground return by more than that and a step lies under it.
  const double below = max_rise + size * std::tan(max_slope_deg * std::numbers::pi / 180.0);
  // Every return is placed: a multiplication, and bounds tested before the truncation.
  const double per_size = 1.0 / size;
  auto columnOf = [&](const Eigen::Vector3f& q) -> std::ptrdiff_t {
    const double column = (double(q.x()) - origin.x()) * per_size;
    const double row = (double(q.y()) - origin.y()) * per_size;
    if (!(column >= 0.0 && row >= 0.0 && column < columns && row < rows)) return -1;
    return std::ptrdiff_t(row) * columns + std::ptrdiff_t(column);
  };
  // Each part of the scan finds its own lowest returns, then the parts' are merged (a minimum
  // in any order is the same).
  const std::size_t cells = std::size_t(columns) * std::size_t(rows);
  std::vector<std::vector<float>> part_lowest(detail::chunkCount(scan.size(), threads));
  detail::parallelChunks(
      scan.size(), threads, [&](std::size_t begin, std::size_t end, std::size_t part) {
        std::vector<float>& lowest = part_lowest[part];
        lowest.assign(cells, std::numeric_limits<float>::infinity());
        for (std::size_t i = begin; i < end; ++i) {
          if (!scan.isValid(i)) continue;
          const Eigen::Vector3f q = mapped(i);
          const std::ptrdiff_t column = columnOf(q);
          if (column >= 0)
            lowest[std::size_t(column)] = std::min(lowest[std::size_t(column)], q.z());
        }
      });
  std::vector<float> lowest = std::move(part_lowest.front());
  for (std::size_t part = 1; part < part_lowest.size(); ++part)
    for (std::size_t cell = 0; cell < cells; ++cell)
      lowest[cell] = std::min(lowest[cell], part_lowest[part][cell]);
  std::vector<std::size_t> own(planes.size(), 0), over(planes.size(), 0);
  std::vector<bool> is_over(ground.size(), false);
  for (std::size_t n = 0; n < ground.size(); ++n) {
    const Eigen::Vector3f& q = ground_mapped[n];
    const std::size_t plane = std::size_t(point_plane[ground[n]]);
    const std::ptrdiff_t column = columnOf(q);
    is_over[n] = column >= 0 && double(q.z()) - double(lowest[std::size_t(column)]) > below;
    ++own[plane];
    over[plane] += is_over[n];
  }
  std::vector<bool> dropped(planes.size(), false);
  std::size_t count = 0;
  for (const int g : analysis.ground_planes) {
    const auto k = std::size_t(g);
    if (g == analysis.reference_ground || double(over[k]) <= kMostlyOver * double(own[k])) continue;
    dropped[k] = true;
    analysis.planes.planes[k].kind = PlaneKind::kOther;
    ++count;
  }
  for (std::size_t n = 0; n < ground.size(); ++n)
    if (is_over[n] || dropped[std::size_t(point_plane[ground[n]])]) point_plane[ground[n]] = -1;
  std::erase_if(analysis.ground_planes, [&](int g) { return dropped[std::size_t(g)]; });
  return count;
}

}  // namespace clearway
