#include "clearway/sensor_geometry.h"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

#include "segmentation/parallel.h"

namespace clearway {
namespace {

constexpr double kPi = std::numbers::pi;

double wrapAngle(double angle) {
  return std::remainder(angle, 2.0 * kPi);  // into [-pi, pi]
}

// A direction's angle about z as a pseudo-angle in [0, 4): a quarter turn per unit, increasing
// with the angle, exact at every multiple of 45 deg, without atan2 (a tenth of the sensor's
// description's time went to it). Straight up or down counts as 0, as atan2(0, 0) does.
double pseudoAngle(double x, double y) {
  const double manhattan = std::abs(x) + std::abs(y);
  if (manhattan == 0.0) return 0.0;
  const double p = y / manhattan;
  if (x >= 0.0) return y >= 0.0 ? p : 4.0 + p;
  return 2.0 - p;
}

// The pseudo-angles of a full turn and of half a turn.
constexpr double kPseudoTurn = 4.0;
constexpr double kPseudoHalfTurn = 2.0;

// The difference of two pseudo-angles, wrapped into [-2, 2].
double wrapPseudoDifference(double difference) {
  if (difference > kPseudoHalfTurn) return difference - kPseudoTurn;
  if (difference < -kPseudoHalfTurn) return difference + kPseudoTurn;
  return difference;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// A multi-beam ring sweeps (nearly) a full turn in azimuth; a RoSi half line sweeps none, a
// nodding scanner's horizontal line at most its field of view (270 deg for most 2D scanners).
constexpr double kRingSweep = 300.0 * kPi / 180.0;
// A ring seen over less than that (a frame cropped to a camera's view, the upper rings of a
// VLP-16 that meet only the buildings on one side) is still a cone about the spin axis: over at
// least this much azimuth, its elevations (the middle 80 % of them) stay within kConeSpread. A
// ring's own spread comes from its lasers' offsets on the head (KITTI's HDL-64E: 0.6-1.3 deg); a
// RoSi fan spans tens of degrees of elevation, a nodding scanner's line as much as its tilt.
constexpr double kPartialRingSweep = 60.0 * kPi / 180.0;
constexpr double kConeSpread = 3.0 * kPi / 180.0;
constexpr double kConeLowShare = 0.1, kConeHighShare = 0.9;
// Along one line, at most this many steps are looked at: the median is settled long before.
constexpr std::size_t kStepsPerLine = 400;
// The closing step of a full turn may be this many times the usual step between lines (a line
// or two lost at the start or end of the turn).
constexpr double kClosingStepFactor = 2.5;
// Lines lost at the start and end of a turn (sky, no returns) leave a gap at most this wide that
// the turn still closes over [rad]; the density check keeps the wedge from showing green.
constexpr double kLargestSeamGap = 15.0 * kPi / 180.0;
// A full turn's steps sum to 360 deg within this much (the closing step included) [rad].
// The lowest a sensor is taken to be above the ground it sees (files with their origin on the
// floor still had the beams start somewhere above it) [m].
constexpr double kLowestBeamHeight = 0.05;
constexpr double kTurnTolerance = 20.0 * kPi / 180.0;

struct LineShape {
  bool usable = false;
  // Sum of |azimuth steps| along the line [rad], measured in pseudo-angles: exact for a line that
  // turns one way (a ring's full turn, a fan's half turn through the zenith), within about 30 %
  // for each back-and-forth of noise. It only tells rings (a full turn) from fans.
  double azimuth_sweep = 0.0;
  double azimuth = 0.0;  // direction of the line's points about z (vector mean) [rad]
  // A fan's plane: fitted to its points (the scanner may sit half a metre from the file's
  // origin, as octomap's does, so the plane need not hold the origin), else, where they lie on a
  // line (a fan that met one flat surface), the plane through the origin and that line. Its
  // normal, and the sum of the points' directions: which way in its plane the fan points.
  bool has_plane = false;  // fitted: the file gives no turntable angle and it has 3 samples
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d direction_sum = Eigen::Vector3d::Zero();
  double step = 0.0;  // median angle between neighbouring returns [rad]
  // A multi-beam ring: a full turn of azimuth, or a partial one at one elevation (a cone).
  bool ring = false;
  // False for a line only found usable (describeSensor shapes a sample of a dense scan's lines).
  bool shaped = true;
};

// The median of acos(cosines[j]) / gaps[j] (angles between neighbouring samples, per return
// between them). acos is decreasing and dividing by one positive gap keeps the order: with every
// gap the same (no invalid return between samples, nearly always) the median angle is that of the
// cosine at the mirrored rank, one acos instead of one per sample. The same value either way.
double medianStep(std::vector<double>& cosines, const std::vector<double>& gaps) {
  const std::size_t n = cosines.size();
  if (std::all_of(gaps.begin(), gaps.end(), [&](double gap) { return gap == gaps.front(); })) {
    const auto mirrored = cosines.begin() + static_cast<std::ptrdiff_t>(n - 1 - n / 2);
    std::nth_element(cosines.begin(), mirrored, cosines.end());
    return std::acos(*mirrored) / gaps.front();
  }
  std::vector<double> steps(n);
  for (std::size_t j = 0; j < n; ++j)
    steps[j] = std::acos(cosines[j]) / gaps[j];
  return median(std::move(steps));
}

// The directions of a line's samples (at most kStepsPerLine of them, evenly spread), to `visit`
// with each sample's point index.
// Every how many returns of `line` one is sampled: at most kStepsPerLine samples.
std::size_t sampleStride(const ScanLine& line) {
  return std::max<std::size_t>(1, line.count / kStepsPerLine);
}

template <typename Visit>
void forSampledDirections(const Scan& scan, const ScanLine& line, Visit&& visit) {
  const std::size_t stride = sampleStride(line);
  for (std::size_t k = 0; k < line.count; k += stride) {
    const std::size_t i = line.first + k;
    if (!scan.isValid(i)) continue;
    const Point3f& p = scan.points[i];
    const Eigen::Vector3d v(p.x, p.y, p.z);
    const double range = v.norm();
    if (range <= 1e-6) continue;
    visit(i, Eigen::Vector3d(v / range));
  }
}

// A fan's plane is fitted to every this many of its samples (at most kStepsPerLine).
constexpr std::size_t kPlaneSampleStride = 4;

// Points spread across the line they lie along by less than this share of their spread along
// it (as variances: 1 % as lengths) lie on a line, and give no plane of their own.
constexpr double kLeastPlanarSpread = 1e-4;

// The normal of a fan's plane: fitted to its `count` points (their sum and the sum of their outer
// products), or where they lie on a line, to their directions from the origin.
Eigen::Vector3d fanNormal(const Eigen::Matrix3d& point_scatter, const Eigen::Vector3d& point_sum,
                          double count, const Eigen::Matrix3d& direction_scatter) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> fit;
  fit.computeDirect(point_scatter - point_sum * point_sum.transpose() / count);
  const Eigen::Vector3d& spread = fit.eigenvalues();  // ascending
  if (spread(1) > kLeastPlanarSpread * spread(2)) return fit.eigenvectors().col(0);
  fit.computeDirect(direction_scatter);
  return fit.eigenvectors().col(0);
}

// Everything but the elevation, which only rings need (medianElevation): a RoSi scan has
// thousands of lines, and the elevations' median was a quarter of their description's time.
LineShape shapeOf(const Scan& scan, const ScanLine& line) {
  LineShape shape;
  // Between neighbouring samples: the cosine of the angle, and the returns it spans. Kept per
  // thread: a line's description is a few hundred instructions per return, and allocating three
  // vectors per line (thousands of lines) cost a tenth of it.
  thread_local std::vector<double> step_cosines, step_gaps, elevation_sines;
  step_cosines.clear();
  step_gaps.clear();
  elevation_sines.clear();
  bool has_previous = false;
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  double previous_azimuth = 0.0;
  std::size_t previous_index = 0;
  const bool fit_plane = !std::isfinite(line.beta);
  std::size_t samples = 0, plane_samples = 0;
  Eigen::Matrix3d direction_scatter = Eigen::Matrix3d::Zero(),
                  point_scatter = Eigen::Matrix3d::Zero();
  Eigen::Vector3d point_sum = Eigen::Vector3d::Zero();
  forSampledDirections(scan, line, [&](std::size_t i, const Eigen::Vector3d& direction) {
    const double azimuth = pseudoAngle(direction.x(), direction.y());
    elevation_sines.push_back(std::clamp(direction.z(), -1.0, 1.0));
    // The fan's plane, only where the file gives no turntable angle (a RoSi's lines carry it),
    // from every kPlaneSampleStride-th sample: a few dozen points fit a plane.
    shape.direction_sum += direction;
    if (fit_plane && samples++ % kPlaneSampleStride == 0) {
      direction_scatter.noalias() += direction * direction.transpose();
      const Point3f& p = scan.points[i];
      const Eigen::Vector3d position(p.x, p.y, p.z);
      point_sum += position;
      point_scatter.noalias() += position * position.transpose();
      ++plane_samples;
    }
    if (has_previous) {
      shape.azimuth_sweep += std::abs(wrapPseudoDifference(azimuth - previous_azimuth));
      // The mean step over the returns between the two samples (invalid ones included).
      step_cosines.push_back(std::clamp(direction.dot(previous), -1.0, 1.0));
      step_gaps.push_back(double(i - previous_index));
    }
    previous = direction;
    previous_index = i;
    previous_azimuth = azimuth;
    has_previous = true;
  });
  if (step_cosines.empty()) return shape;
  shape.usable = true;
  shape.azimuth_sweep *= 2.0 * kPi / kPseudoTurn;
  shape.azimuth = std::atan2(shape.direction_sum.y(), shape.direction_sum.x());
  shape.step = medianStep(step_cosines, step_gaps);
  shape.has_plane = plane_samples >= 3;
  if (shape.has_plane)
    shape.normal = fanNormal(point_scatter, point_sum, double(plane_samples), direction_scatter);
  shape.ring = shape.azimuth_sweep >= kRingSweep;
  if (!shape.ring && shape.azimuth_sweep >= kPartialRingSweep) {
    // Only lines that sweep some azimuth pay for the quantiles (a RoSi's fans sweep none).
    const std::size_t n = elevation_sines.size();
    auto quantile = [&](double share) {
      const auto at = elevation_sines.begin() +
                      static_cast<std::ptrdiff_t>(std::min(n - 1, std::size_t(share * double(n))));
      std::nth_element(elevation_sines.begin(), at, elevation_sines.end());
      return std::asin(*at);
    };
    const double low = quantile(kConeLowShare), high = quantile(kConeHighShare);
    shape.ring = high - low <= kConeSpread;
  }
  return shape;
}

// At most this many lines are shaped (shapeOf) where every line carries its turntable angle.
constexpr std::size_t kShapedLines = 512;

// Every how many of the `usable` lines one is shaped: 1 unless every line carries its turntable
// angle (then the shapes give only statistics) and more than kShapedLines are usable.
std::size_t shapingStride(const Scan& scan, std::size_t usable) {
  const bool every_angle =
      std::all_of(scan.lines.begin(), scan.lines.end(),
                  [](const ScanLine& line) { return std::isfinite(line.beta); });
  if (!every_angle || usable <= kShapedLines) return 1;
  return (usable + kShapedLines - 1) / kShapedLines;
}

// A line not (yet) shaped: usable exactly where shapeOf finds it so (two sampled directions), its
// shape otherwise the default one, and not counted in the statistics.
LineShape unshapedLine(const Scan& scan, const ScanLine& line) {
  LineShape shape;
  shape.shaped = false;
  // forSampledDirections' samples, counted up to two.
  const std::size_t stride = sampleStride(line);
  std::size_t samples = 0;
  for (std::size_t k = 0; k < line.count && samples < 2; k += stride) {
    const std::size_t i = line.first + k;
    const Point3f& p = scan.points[i];
    if (scan.isValid(i) && Eigen::Vector3d(p.x, p.y, p.z).norm() > 1e-6) ++samples;
  }
  shape.usable = samples >= 2;
  return shape;
}

// The median elevation of a line's samples [rad]. The sines of the elevations: asin is
// increasing, so their median's is the elevations' median.
double medianElevation(const Scan& scan, const ScanLine& line) {
  std::vector<double> elevation_sines;
  forSampledDirections(scan, line, [&](std::size_t, const Eigen::Vector3d& direction) {
    elevation_sines.push_back(std::clamp(direction.z(), -1.0, 1.0));
  });
  return std::asin(median(std::move(elevation_sines)));
}

// A fan's plane holds the turntable axis, so the axis is the direction least spread across the
// fans' normals. Vertical fans (a RoSi turning about the vertical) are told apart by the direction
// of their points about z; fans about an axis more than this far from the vertical (a nodding
// scanner's fans, tilted about a horizontal axis, all point forward) are not, and their angle is
// taken about the axis itself.
constexpr double kLeastTiltedAxisDeg = 45.0;

// Per shape, the angle that orders the fans side by side: the direction of their points about z,
// or about the turntable axis the fans' planes hold when it lies far from the vertical (then
// `tilted_axis` is set to it).
std::vector<double> fanAngles(const std::vector<LineShape>& shapes,
                              std::optional<Eigen::Vector3d>& tilted_axis) {
  std::vector<double> angles;
  for (const LineShape& shape : shapes)
    angles.push_back(shape.azimuth);
  Eigen::Matrix3d normals = Eigen::Matrix3d::Zero();
  std::size_t fitted = 0;
  for (const LineShape& shape : shapes)
    if (shape.has_plane) {
      normals.noalias() += shape.normal * shape.normal.transpose();
      ++fitted;
    }
  if (fitted < 2) return angles;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> spread;
  spread.computeDirect(normals);
  const Eigen::Vector3d axis = spread.eigenvectors().col(0);
  if (std::abs(axis.z()) >= std::cos(kLeastTiltedAxisDeg * kPi / 180.0)) return angles;
  tilted_axis = axis;
  // Across the axis: the horizontal direction across it, and the one across both.
  const Eigen::Vector3d first = axis.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d second = axis.cross(first);
  // Each fan's direction in its plane across the axis, the way its points lie (a line with too
  // few samples for a plane: the direction of its points, across the axis).
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    Eigen::Vector3d forward = shapes[k].direction_sum;
    if (shapes[k].has_plane) {
      forward = axis.cross(shapes[k].normal);
      if (forward.dot(shapes[k].direction_sum) < 0.0) forward = -forward;
    }
    angles[k] = std::atan2(forward.dot(second), forward.dot(first));
  }
  return angles;
}

}  // namespace

std::string_view sensorKindName(SensorKind kind) {
  switch (kind) {
    case SensorKind::kRotating2D:
      return "rotating 2D";
    case SensorKind::kMultiBeam:
      return "multi-beam";
    case SensorKind::kUnknown:
      break;
  }
  return "unknown";
}

SensorGeometry describeSensor(const Scan& scan, int threads) {
  SensorGeometry sensor;
  sensor.lines = scan.lines.size();
  if (scan.lines.size() < 2) return sensor;
  // A few trigonometric functions per return: 10 % of a RoSi scan's pipeline on one thread.
  // Which lines are usable (two sampled directions), then the shapes of those lines. Where every
  // line carries its turntable angle, the shapes give only statistics (the median step along a
  // line, whether most are rings): a few hundred usable lines settle them, and a dense RoSi scan's
  // tens of thousands (10M points: 55,556 lines) need only be found usable.
  std::vector<LineShape> every_shape(scan.lines.size());
  detail::parallelChunks(scan.lines.size(), threads,
                         [&](std::size_t begin, std::size_t end, std::size_t) {
                           for (std::size_t l = begin; l < end; ++l)
                             every_shape[l] = unshapedLine(scan, scan.lines[l]);
                         });
  std::vector<std::size_t> used;  // line index of each usable line
  for (std::size_t l = 0; l < scan.lines.size(); ++l)
    if (every_shape[l].usable) used.push_back(l);
  const std::size_t shaped_every = shapingStride(scan, used.size());
  detail::parallelChunks(used.size(), threads,
                         [&](std::size_t begin, std::size_t end, std::size_t) {
                           for (std::size_t k = begin; k < end; ++k)
                             if (k % shaped_every == 0)
                               every_shape[used[k]] = shapeOf(scan, scan.lines[used[k]]);
                         });
  std::vector<LineShape> shapes;
  shapes.reserve(used.size());
  for (const std::size_t l : used)
    shapes.push_back(every_shape[l]);
  if (shapes.size() < 2) return sensor;
  sensor.line_angle.assign(scan.lines.size(), std::numeric_limits<double>::quiet_NaN());
  std::vector<double> along;
  std::size_t rings = 0, shaped = 0;
  for (const LineShape& s : shapes) {
    if (!s.shaped) continue;
    along.push_back(s.step);
    rings += s.ring;
    ++shaped;
  }
  sensor.along_line_step = median(along);

  // Most lines are rings (the upper median: at least n - n / 2 of n).
  if (shaped > 0 && rings >= shaped - shaped / 2) {
    // Rings: the step between them is the elevation step, whatever order the file keeps them in.
    sensor.kind = SensorKind::kMultiBeam;
    detail::parallelChunks(
        used.size(), threads, [&](std::size_t begin, std::size_t end, std::size_t) {
          for (std::size_t k = begin; k < end; ++k)
            sensor.line_angle[used[k]] = medianElevation(scan, scan.lines[used[k]]);
        });
    std::vector<double> elevations;
    for (const std::size_t l : used)
      elevations.push_back(sensor.line_angle[l]);
    std::sort(elevations.begin(), elevations.end());
    std::vector<double> gaps;
    for (std::size_t k = 1; k < elevations.size(); ++k)
      gaps.push_back(elevations[k] - elevations[k - 1]);
    sensor.between_line_step = median(gaps);
    return sensor;
  }

  // Lines fanning about a turntable axis: their angles are beta when the file gives it, else
  // the direction of their points about z (vertical fans) or about the axis their planes hold
  // (fans about an axis far from the vertical: a nodding scanner's).
  sensor.kind = SensorKind::kRotating2D;
  std::vector<double> angles = fanAngles(shapes, sensor.tilted_axis);
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    const double beta = scan.lines[used[k]].beta;
    if (std::isfinite(beta)) angles[k] = beta;
  }
  for (std::size_t k = 0; k < shapes.size(); ++k)
    sensor.line_angle[used[k]] = angles[k];
  std::vector<double> steps;
  double total = 0.0;
  for (std::size_t k = 1; k < angles.size(); ++k) {
    const double step = wrapAngle(angles[k] - angles[k - 1]);
    steps.push_back(std::abs(step));
    total += step;
  }
  // The step between lines side by side: the median gap between their sorted angles (a wide
  // 2D field writes a fan's two halves half a turn apart, one after the other).
  std::vector<double> sorted;
  for (const double angle : angles)
    sorted.push_back(std::remainder(angle, 2.0 * kPi));
  std::sort(sorted.begin(), sorted.end());
  std::vector<double> gaps;
  // Lines at the same angle (a fan's up and down sweeps) are not neighbours apart.
  constexpr double kSameAngle = 1e-4;  // [rad]
  for (std::size_t k = 1; k < sorted.size(); ++k)
    if (sorted[k] - sorted[k - 1] > kSameAngle) gaps.push_back(sorted[k] - sorted[k - 1]);
  sensor.between_line_step = median(gaps);
  const double closing = wrapAngle(angles.front() - angles.back());
  const bool small_closing =
      std::abs(closing) <= std::max(kClosingStepFactor * sensor.between_line_step, kLargestSeamGap);
  // Once around and back to the start, or more than once around (the turntable overran: the
  // last lines overlap the first ones, and the turn has no gap at all).
  const bool once_around =
      small_closing && std::abs(std::abs(total + closing) - 2.0 * kPi) <= kTurnTolerance;
  const bool overran = std::abs(total) >= 2.0 * kPi - kTurnTolerance;
  sensor.closed_turn = angles.size() >= 3 && (once_around || overran);
  return sensor;
}

double expectedGroundSpacing(const SensorGeometry& sensor, double range, double height) {
  if (height <= 0.0) return std::numeric_limits<double>::infinity();
  const double slant_squared = range * range + height * height;
  // The step that runs towards the sensor is stretched on the ground by slant^2 / height; the one
  // that runs across is not. A RoSi's fans run towards it, a nodding scanner's fans (about a
  // tilted axis) and a multi-beam head's rings across.
  const bool lines_across = sensor.kind == SensorKind::kMultiBeam || sensor.tilted_axis;
  const double radial_step = lines_across ? sensor.between_line_step : sensor.along_line_step;
  const double tangential_step = lines_across ? sensor.along_line_step : sensor.between_line_step;
  return std::max(slant_squared / height * radial_step, range * tangential_step);
}

namespace {

// Where a beam's move by `step` about direction `du` (a unit tangent at `u`, or one scaled by the
// distance factor of a turn about an axis) carries its sample on the ground `drop` below: the
// move's part sideways of the beam and its part along it, on the ground.
struct GroundMove {
  double sideways = 0.0, radial = 0.0;
};
std::optional<GroundMove> groundMove(const Eigen::Vector3d& u, const Eigen::Vector3d& du,
                                     double step, const Eigen::Vector3d& up, double drop) {
  const double facing = up.dot(u);  // negative: the beam goes down to the ground
  if (facing > -1e-3) return std::nullopt;
  const double t = -drop / facing;
  const double dt = drop * up.dot(du) / (facing * facing);
  Eigen::Vector3d move = (t * du + dt * u) * step;
  move -= move.dot(up) * up;
  Eigen::Vector3d beam = u - facing * up;
  if (beam.norm() < 1e-6) return GroundMove{move.norm(), 0.0};
  beam.normalize();
  const double along = move.dot(beam);
  return GroundMove{(move - along * beam).norm(), std::abs(along)};
}

// How far a beam's move (groundMove) carries its sample where nothing could stand between the two
// samples unseen: its part sideways of the beam, and its part along the beam up to what the
// farther beam protects (2 x range x step). Infinity for a beam that grazes the ground or points
// up.
double unprotectedMove(const Eigen::Vector3d& u, const Eigen::Vector3d& du, double step,
                       const Eigen::Vector3d& up, double drop, double range) {
  const std::optional<GroundMove> move = groundMove(u, du, step, up, drop);
  if (!move) return std::numeric_limits<double>::infinity();
  return std::max(move->sideways, std::min(move->radial, 2.0 * range * step));
}

// A turn about the sweep's axis that lifts the beam instead of moving it sideways (the axis leans
// away from upright: a RoSi whose turntable points forward lays its lines one above the other
// beside it) carries the sample along the ground, stretched by the grazing angle. The farther beam
// passes over the nearer sample as high as the two beams lie apart up and down there (range x step
// x the turn's share in the beam's upright plane), and an obstacle lower than that, twice as wide,
// hides between them. Returns at most `sideways` (the turn's sideways part, already counted) where
// the lift cannot exceed it: an upright axis lifts nothing, and most cells are not worth the
// ground's geometry. Infinity for a beam that grazes the ground or points up.
double unprotectedLift(const Eigen::Vector3d& u, const Eigen::Vector3d& du, double step,
                       const Eigen::Vector3d& up, double drop, double range, double sideways) {
  const Eigen::Vector3d upright = (up - up.dot(u) * u).normalized();
  const double apart_up_and_down = range * step * std::abs(du.dot(upright));
  if (2.0 * apart_up_and_down <= sideways) return sideways;
  const std::optional<GroundMove> move = groundMove(u, du, step, up, drop);
  if (!move) return std::numeric_limits<double>::infinity();
  return std::min(move->radial, 2.0 * apart_up_and_down);
}

// hiddenObstacleSize() for fans about a tilted axis `axis` (a nodding scanner): within a fan the
// beam turns towards the axis in the fan's plane; from fan to fan it turns about the axis, which
// carries its sample towards or away from the sensor on the ground, no longer sideways only.
double hiddenAboutTiltedAxis(const SensorGeometry& sensor, const Eigen::Vector3d& axis,
                             const Eigen::Vector3d& u, const Eigen::Vector3d& up, double drop,
                             double range) {
  const Eigen::Vector3d towards_axis = axis - u.dot(axis) * u;
  const double within =
      towards_axis.norm() < 1e-9
          ? 0.0
          : unprotectedMove(u, towards_axis.normalized(), sensor.along_line_step, up, drop, range);
  const double across =
      unprotectedMove(u, axis.cross(u), sensor.between_line_step, up, drop, range);
  return std::max(within, across);
}

}  // namespace

double hiddenObstacleSize(const SensorGeometry& sensor, const Eigen::Vector3d& point,
                          const Eigen::Vector3d& up, double height) {
  if (sensor.kind == SensorKind::kUnknown || sensor.along_line_step <= 0.0 ||
      sensor.between_line_step <= 0.0)
    return std::numeric_limits<double>::infinity();
  const double range = point.norm();
  if (range <= 0.0) return 0.0;
  if (sensor.kind == SensorKind::kRotating2D && sensor.tilted_axis)
    return hiddenAboutTiltedAxis(sensor, *sensor.tilted_axis, point / range, up,
                                 std::max(height, kLowestBeamHeight), range);
  // The sweep's axis is the frame's z: the turntable axis of a RoSi file, the spin axis of a
  // multi-beam head. Across the sweep, neighbouring beams are this far apart, unprotected, where
  // the axis stands upright; where it leans, as far as the turn lifts the beam (unprotectedLift).
  // A 0.13 m box beside a RoSi whose turntable pointed forward lay between two lines one above
  // the other, their ground samples 0.6 m apart: counted sideways, 0.19 m, and driven over (a
  // helper's clutter scene, 100 lines tilted 15 deg).
  const double from_axis = point.head<2>().norm();
  const double across_step =
      sensor.kind == SensorKind::kMultiBeam ? sensor.along_line_step : sensor.between_line_step;
  const double within_step =
      sensor.kind == SensorKind::kMultiBeam ? sensor.between_line_step : sensor.along_line_step;
  const double drop = std::max(height, kLowestBeamHeight);
  const Eigen::Vector3d u = point / range;
  const double sideways = from_axis * across_step;
  const double across = std::max(sideways, unprotectedLift(u, Eigen::Vector3d::UnitZ().cross(u),
                                                           across_step, up, drop, range, sideways));
  // Within a fan (the beams of one line, or one ring to the next), the step moves the ground
  // sample by d(hit)/d(angle) x step. Its part along the beam's horizontal direction is protected
  // by the farther beam (worth 2 x range x step); its part sideways is not.
  // The beam's direction turned up by its elevation step: d(u)/d(elevation) =
  // (-sin e cos a, -sin e sin a, cos e), with cos e the horizontal part of u and (cos a, sin a) its
  // horizontal direction (no trigonometry: this runs for every ground cell).
  const double horizontal = u.head<2>().norm();
  const Eigen::Vector3d du =
      horizontal > 1e-12
          ? Eigen::Vector3d(-u.z() * u.x() / horizontal, -u.z() * u.y() / horizontal, horizontal)
          : Eigen::Vector3d(-u.z(), 0.0, 0.0);  // straight up or down: azimuth 0
  return std::max(across, unprotectedMove(u, du, within_step, up, drop, range));
}

double vouchedRange(const SensorGeometry& sensor, double height, double largest_hidden,
                    double limit) {
  // Walked outwards in steps of this much [m]: finer than any robot, coarse enough to be cheap.
  constexpr double kRangeStep = 0.1;
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  for (double range = kRangeStep; range <= limit; range += kRangeStep) {
    const Eigen::Vector3d ground(range, 0.0, -height);
    if (!(hiddenObstacleSize(sensor, ground, up, height) <= largest_hidden))
      return range - kRangeStep;
  }
  return limit;
}

}  // namespace clearway
