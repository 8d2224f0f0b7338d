#include "clearway/sim/rosi_simulator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <sstream>
#include <stdexcept>

#include "clearway/pose.h"
#include "clearway/segmentation/params.h"
#include "clearway/sim/ray_caster.h"

namespace clearway::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// A depth edge: neighbouring beams this much further apart than the beam itself.
constexpr double kMixedPixelJump = 0.3;

// Mixed into the seed of the lost returns' generator, so that it does not draw what the range
// noise's does.
constexpr std::uint32_t kLossSeed = 0x9e3779b9U;

}  // namespace

int SensorModel::linesForSpeed(double degrees_per_second) {
  return std::max(1, int(std::lround(kLineRateHz * 360.0 / degrees_per_second)));
}

Eigen::Isometry3d ScannerPlacement::worldFromScanner() const {
  // Scaled first: an axis of 1e300 components overflowed its norm into a zero vector.
  const Eigen::Vector3d z = unitDirection(axis).value_or(Eigen::Vector3d::UnitZ());
  // beta = 0 points "up" where the axis allows it, else along world x.
  Eigen::Vector3d reference = Eigen::Vector3d::UnitZ();
  if (std::abs(z.dot(reference)) > 0.95) reference = Eigen::Vector3d::UnitX();
  Eigen::Vector3d x = (reference - reference.dot(z) * z).normalized();
  x = Eigen::AngleAxisd(axis_roll_deg * kDeg, z) * x;
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear().col(0) = x;
  pose.linear().col(1) = y;
  pose.linear().col(2) = z;
  pose.translation() = position;
  return pose;
}

ScannerPlacement defaultPlacement(const Scene& scene) {
  ScannerPlacement placement;
  placement.position = scene.scanner_position;
  placement.axis = scene.scanner_axis;
  return placement;
}

std::string vectorText(const Eigen::Vector3d& v) {
  std::string text = "[";  // appended: GCC 12 warned (-Wrestrict) on "[" + a temporary
  for (int i = 0; i < 3; ++i)
    text += readableNumber(v[i]) + (i < 2 ? ", " : "]");
  return text;
}

std::string placementProblem(const ScannerPlacement& placement, const std::string& prefix) {
  // 1e308 put the scanner off every map: its rays met nothing, and eval placed the map there.
  if (!placement.position.allFinite() ||
      !(placement.position.cwiseAbs().maxCoeff() <= kFarthestScannerPosition))
    return prefix + "position = " + vectorText(placement.position) +
           " lies more than 10 km from the origin";
  if (!unitDirection(placement.axis))
    return prefix + "axis = " + vectorText(placement.axis) +
           " is no direction (zero or not finite)";
  if (!(std::abs(placement.axis_roll_deg) <= 360.0))
    return prefix + "axis_roll_deg = " + readableNumber(placement.axis_roll_deg) +
           " is outside -360 .. 360";
  return {};
}

std::vector<double> simulateLineRanges(const Scene& scene, const RayCaster& caster,
                                       const SensorModel& sensor, const ScannerPlacement& placement,
                                       double beta, std::uint32_t seed) {
  const Eigen::Isometry3d world_from_scanner = placement.worldFromScanner();
  std::mt19937 random(seed);
  std::normal_distribution<double> noise(0.0, sensor.range_noise_sigma);
  std::vector<double> ranges(std::size_t(sensor.points_per_line),
                             std::numeric_limits<double>::quiet_NaN());
  for (int k = 0; k < sensor.points_per_line; ++k) {
    const double alpha = k * sensor.alpha_step_deg * kDeg;
    const Eigen::Vector3d local(std::cos(beta) * std::cos(alpha), std::sin(beta) * std::cos(alpha),
                                std::sin(alpha));
    const auto hit = caster.cast(world_from_scanner.translation(),
                                 world_from_scanner.linear() * local, sensor.max_range);
    if (!hit || scene.primitives[std::size_t(hit->primitive)].transparent) continue;
    ranges[std::size_t(k)] = hit->distance + noise(random);
  }
  return ranges;
}

SimulatedScan simulateRosi(const Scene& scene, const SensorModel& sensor,
                           const ScannerPlacement& placement, const ProgressCallback& progress) {
  // Its truth file would be refused: eval holds the placement to the same (--position 0,0,1e308
  // gave a scan of no returns).
  if (const std::string problem = placementProblem(placement, "scanner "); !problem.empty())
    throw std::invalid_argument(problem);
  const RayCaster caster(scene);
  const Eigen::Isometry3d world_from_scanner = placement.worldFromScanner();
  const Eigen::Matrix3d rotation = world_from_scanner.linear();
  const Eigen::Vector3d origin = world_from_scanner.translation();
  // A scanner inside a solid sees the solid's far side from within, which no scanner can: the
  // scan would be a scene that does not exist, and its truth would judge the map against it.
  for (const Primitive& primitive : scene.primitives)
    if (primitive.holdsInside(origin)) {
      std::ostringstream where;
      where << "the scanner at (" << origin.x() << ", " << origin.y() << ", " << origin.z()
            << ") is inside '" << primitive.name << "' of the scene '" << scene.name
            << "': place it in free space";
      throw std::invalid_argument(where.str());
    }
  std::mt19937 random(sensor.seed);
  std::normal_distribution<double> noise(0.0, sensor.range_noise_sigma);
  // The lost returns' own generator: with no dropout, nothing is drawn from it.
  std::mt19937 losses(sensor.seed ^ kLossSeed);
  std::bernoulli_distribution lost(std::clamp(sensor.dropout, 0.0, 1.0));
  const auto nan = std::numeric_limits<float>::quiet_NaN();

  SimulatedScan result;
  Scan& scan = result.scan;
  GroundTruth& truth = result.truth;
  const std::size_t total = std::size_t(sensor.lines) * std::size_t(sensor.points_per_line);
  scan.points.reserve(total);
  scan.status.reserve(total);
  scan.intensity.reserve(total);
  scan.alpha.reserve(total);
  truth.classes.reserve(total);
  truth.surfaces.reserve(total);
  std::map<int, std::size_t> surface_counts;

  auto rangeAlong = [&](double beta, double alpha) {
    const Eigen::Vector3d local(std::cos(beta) * std::cos(alpha), std::sin(beta) * std::cos(alpha),
                                std::sin(alpha));
    return caster.cast(origin, rotation * local, sensor.max_range);
  };

  const auto pushNoReturn = [&] {
    scan.points.push_back({nan, nan, nan});
    scan.status.push_back(PointStatus::kNoReturn);
    scan.intensity.push_back(0.0F);
    truth.classes.push_back(PointClass::kNone);
    truth.surfaces.push_back(-1);
  };
  for (int line = 0; line < sensor.lines; ++line) {
    const double beta = 2.0 * std::numbers::pi * line / sensor.lines;
    scan.lines.push_back({scan.size(), std::size_t(sensor.points_per_line), beta});
    for (int k = 0; k < sensor.points_per_line; ++k) {
      const double alpha = k * sensor.alpha_step_deg * kDeg;
      const auto hit = rangeAlong(beta, alpha);
      scan.alpha.push_back(float(alpha));
      const bool glass = hit && scene.primitives[std::size_t(hit->primitive)].transparent;
      if (!hit || glass) {
        pushNoReturn();
        continue;
      }
      double range = hit->distance;
      if (sensor.mixed_pixels) {
        const double half_beam = sensor.alpha_step_deg * kDeg / 2.0;
        const auto before = rangeAlong(beta, alpha - half_beam);
        const auto after = rangeAlong(beta, alpha + half_beam);
        for (const auto& neighbour : {before, after})
          if (neighbour && std::abs(neighbour->distance - range) > kMixedPixelJump)
            range = (range + neighbour->distance) / 2.0;
      }
      range += noise(random);
      // Drawn after the hit's noise, lost or not: the rest of the scan does not depend on losses.
      if (sensor.dropout > 0.0 && lost(losses)) {
        pushNoReturn();
        continue;
      }
      const Primitive& primitive = scene.primitives[std::size_t(hit->primitive)];
      const Eigen::Vector3d direction(std::cos(beta) * std::cos(alpha),
                                      std::sin(beta) * std::cos(alpha), std::sin(alpha));
      const Eigen::Vector3d p = direction * range;
      scan.points.push_back({float(p.x()), float(p.y()), float(p.z())});
      scan.status.push_back(PointStatus::kValid);
      const double incidence = std::abs(hit->normal.dot(rotation * direction));
      scan.intensity.push_back(float(1000.0 * primitive.remission * std::sqrt(incidence)));
      const int id = surfaceId(hit->primitive, hit->face);
      truth.classes.push_back(primitive.point_class);
      truth.surfaces.push_back(id);
      ++surface_counts[id];
    }
    if (line % 32 == 0) reportProgress(progress, double(line) / sensor.lines);
  }

  // Describe every surface that was seen, in the scanner frame.
  for (const auto& [id, count] : surface_counts) {
    const int index = id / 8, face = id % 8;
    const Primitive& primitive = scene.primitives[std::size_t(index)];
    SurfaceTruth surface;
    surface.id = id;
    surface.primitive = primitive.name;
    surface.face = face;
    surface.point_class = primitive.point_class;
    surface.points = count;
    surface.planar = primitive.shape == Shape::kBox || face != 0;
    if (surface.planar) {
      Eigen::Vector3d local_normal = Eigen::Vector3d::Zero();
      Eigen::Vector3d local_point = Eigen::Vector3d::Zero();
      if (primitive.shape == Shape::kBox) {
        const double sign = face % 2 == 0 ? -1.0 : 1.0;
        local_normal[face / 2] = sign;
        local_point[face / 2] = sign * primitive.size[face / 2] / 2.0;
      } else {
        const double sign = face == 1 ? -1.0 : 1.0;
        local_normal.z() = sign;
        local_point.z() = sign * primitive.size.z() / 2.0;
      }
      const Eigen::Matrix3d primitive_rotation = primitive.rotation();
      const Eigen::Vector3d world_normal = primitive_rotation * local_normal;
      const Eigen::Vector3d world_point = primitive.center + primitive_rotation * local_point;
      surface.normal = rotation.transpose() * world_normal;
      surface.offset = surface.normal.dot(world_from_scanner.inverse() * world_point);
    }
    truth.seen_surfaces.push_back(surface);
  }

  // The arm's kinematics tell the RoSi where it is; the PCD keeps this as its VIEWPOINT.
  SensorPose pose;
  for (int r = 0; r < 3; ++r) {
    pose.position[std::size_t(r)] = origin[r];
    for (int c = 0; c < 3; ++c)
      pose.rotation[std::size_t(3 * r + c)] = rotation(r, c);
  }
  scan.sensor_pose = pose;
  scan.metadata.format = "simulated rosi";
  scan.metadata.frame = "RoSi scanner frame: metres, z = turntable axis";
  scan.metadata.source_path = "simulated:" + scene.name;
  truth.scene = scene;
  truth.sensor = sensor;
  truth.placement = placement;
  reportProgress(progress, 1.0);
  return result;
}

}  // namespace clearway::sim
