#include "clearway/eval/robot_fit.h"

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

namespace clearway::eval {
namespace {

sim::Scene walkableOnly(const sim::Scene& scene) {
  sim::Scene walkable;
  for (const sim::Primitive& primitive : scene.primitives)
    if (primitive.point_class == PointClass::kGround ||
        primitive.point_class == PointClass::kStairs)
      walkable.primitives.push_back(primitive);
  return walkable;
}

struct OrientedBox {
  Eigen::Vector3d center;
  Eigen::Matrix3d axes;  // columns
  Eigen::Vector3d half;
};

// Added to the absolute rotation terms of the separating-axis test: when two box axes are
// parallel their cross product vanishes, and rounding must not make it separate the boxes.
constexpr double kParallelAxisSlack = 1e-9;

// Separating-axis test for two oriented boxes.
bool intersects(const OrientedBox& a, const OrientedBox& b) {
  const Eigen::Matrix3d r = a.axes.transpose() * b.axes;
  const Eigen::Matrix3d abs_r = r.cwiseAbs().array() + kParallelAxisSlack;
  const Eigen::Vector3d t = a.axes.transpose() * (b.center - a.center);
  for (int i = 0; i < 3; ++i)
    if (std::abs(t[i]) > a.half[i] + abs_r.row(i).dot(b.half)) return false;
  for (int j = 0; j < 3; ++j)
    if (std::abs(t.dot(r.col(j))) > abs_r.col(j).dot(a.half) + b.half[j]) return false;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const double distance = std::abs(t[i2] * r(i1, j) - t[i1] * r(i2, j));
      const double reach = a.half[i1] * abs_r(i2, j) + a.half[i2] * abs_r(i1, j) +
                           b.half[j1] * abs_r(i, j2) + b.half[j2] * abs_r(i, j1);
      if (distance > reach) return false;
    }
  }
  return true;
}

// A cylinder's box turned by 45 deg about the cylinder's axis. The body meets the cylinder only if
// it meets both boxes, and where they overlap (an octagon around the circle) reaches at most 8 %
// of the radius beyond the cylinder, where the box alone reaches 41 % beyond it at its corners: a
// pipe bridge's box hung 3 mm into a robot's top where the pipe itself cleared it by 3 cm.
OrientedBox turnedAboutAxis(const OrientedBox& cylinder_box) {
  const Eigen::Matrix3d eighth_turn =
      Eigen::AngleAxisd(std::numbers::pi / 4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return {cylinder_box.center, cylinder_box.axes * eighth_turn, cylinder_box.half};
}

// Spacing of the ground samples under the footprint [m].
constexpr double kSampleSpacing = 0.15;
// The ground under the robot is cast for downwards from this far above its centre, so a step up
// under the footprint is found too [m] ...
constexpr double kCastFromAbove = 1.0;
// ... over at most this far (the truth scenes are far smaller) [m] ...
constexpr double kLongestCast = 100.0;
// ... and a surface is ground the robot stands on when its normal's up component is at least this
// (at most 60 deg from vertical; steeper is a wall's side, not a floor).
constexpr double kMinGroundNormalUp = 0.5;

// Where two walkable surfaces meet between two ground samples is found to this [m].
constexpr double kStepSearchPrecision = 0.002;
// Walkable surfaces tilted against each other (the outdoor scene's paving slabs) leave a V-shaped
// crack a few millimetres wide at their joint, which a wheel rolls over. A vertical probe that
// falls into one (it misses, or meets a slab's side face) takes the higher of the surfaces this
// far to either side [m].
constexpr double kCrackWidth = 0.01;

}  // namespace

RobotFit::RobotFit(const sim::Scene& scene)
    : scene_(scene), walkable_(walkableOnly(scene)), walkable_caster_(walkable_) {}

std::optional<RobotFit::GroundSample> RobotFit::groundSample(double x, double y,
                                                             double from_z) const {
  auto probe = [&](double px, double py) -> std::optional<GroundSample> {
    const auto hit =
        walkable_caster_.cast({px, py, from_z}, -Eigen::Vector3d::UnitZ(), kLongestCast);
    if (!hit || hit->normal.z() < kMinGroundNormalUp) return std::nullopt;
    return GroundSample{from_z - hit->distance, hit->primitive, hit->face, hit->normal};
  };
  if (const auto sample = probe(x, y)) return sample;
  // Fell into a crack: the higher of the surfaces either side carries the robot.
  std::optional<GroundSample> carried;
  for (const auto& [dx, dy] : {std::pair{kCrackWidth, 0.0}, std::pair{-kCrackWidth, 0.0},
                               std::pair{0.0, kCrackWidth}, std::pair{0.0, -kCrackWidth}})
    if (const auto sample = probe(x + dx, y + dy);
        sample && (!carried || sample->height > carried->height))
      carried = sample;
  return carried;
}

std::optional<double> RobotFit::groundHeight(double x, double y, double from_z) const {
  const auto sample = groundSample(x, y, from_z);
  if (!sample) return std::nullopt;
  return sample->height;
}

std::optional<double> RobotFit::stepBetween(const Eigen::Vector2d& p, const GroundSample& at_p,
                                            const Eigen::Vector2d& q, const GroundSample& at_q,
                                            double from_z) const {
  auto sameSurface = [](const GroundSample& a, const GroundSample& b) {
    return a.primitive == b.primitive && a.face == b.face;
  };
  if (sameSurface(at_p, at_q)) return 0.0;
  // Where the surfaces meet, found by halving the stretch between the samples down to
  // kStepSearchPrecision; then each surface's plane height there.
  Eigen::Vector2d near_p = p, near_q = q;
  GroundSample beyond_meet = at_q;
  while ((near_q - near_p).norm() > kStepSearchPrecision) {
    const Eigen::Vector2d middle = (near_p + near_q) / 2;
    const auto sample = groundSample(middle.x(), middle.y(), from_z);
    if (!sample) return std::nullopt;
    if (sameSurface(*sample, at_p)) {
      near_p = middle;
    } else {
      near_q = middle;
      beyond_meet = *sample;
    }
  }
  // A third surface between the two (a tread narrower than the samples' spacing): the samples'
  // own heights apart, as a whole.
  if (!sameSurface(beyond_meet, at_q)) return std::abs(at_p.height - at_q.height);
  const Eigen::Vector2d meet = (near_p + near_q) / 2;
  auto heightAt = [&](const Eigen::Vector2d& at, const GroundSample& sample) {
    const Eigen::Vector2d run = meet - at;
    return sample.height -
           (sample.normal.x() * run.x() + sample.normal.y() * run.y()) / sample.normal.z();
  };
  return std::abs(heightAt(p, at_p) - heightAt(q, at_q));
}

bool RobotFit::fits(const sim::RobotBox& robot, const Eigen::Vector3d& center, double yaw) const {
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d along = turn.col(0), across = turn.col(1);
  const double from_z = center.z() + kCastFromAbove;
  const auto center_height = groundHeight(center.x(), center.y(), from_z);
  if (!center_height) return false;
  // Ground under the whole footprint, with no step higher than the robot can take.
  const int n_along = std::max(2, int(std::ceil(robot.length / kSampleSpacing)) + 1);
  const int n_across = std::max(2, int(std::ceil(robot.width / kSampleSpacing)) + 1);
  std::vector<Eigen::Vector2d> places(std::size_t(n_along * n_across));
  std::vector<GroundSample> samples(places.size());
  double highest = *center_height;
  auto stepsTooHigh = [&](std::size_t a, std::size_t b) {
    const auto step = stepBetween(places[a], samples[a], places[b], samples[b], from_z);
    return !step || *step > robot.max_step;
  };
  for (int i = 0; i < n_along; ++i) {
    for (int j = 0; j < n_across; ++j) {
      const double u = -robot.length / 2 + robot.length * i / (n_along - 1);
      const double v = -robot.width / 2 + robot.width * j / (n_across - 1);
      const Eigen::Vector3d p = center + u * along + v * across;
      const auto sample = groundSample(p.x(), p.y(), from_z);
      if (!sample) return false;
      const auto index = std::size_t(i * n_across + j);
      places[index] = p.head<2>();
      samples[index] = *sample;
      highest = std::max(highest, sample->height);
      if (i > 0 && stepsTooHigh(std::size_t((i - 1) * n_across + j), index)) return false;
      if (j > 0 && stepsTooHigh(index - 1, index)) return false;
    }
  }
  // The body, from the step height above the highest ground sample to the robot's height.
  OrientedBox body;
  const double bottom = highest + robot.max_step;
  const double top = *center_height + robot.height;
  if (top <= bottom) return true;
  body.center = {center.x(), center.y(), (bottom + top) / 2};
  body.axes = turn;
  body.half = {robot.length / 2, robot.width / 2, (top - bottom) / 2};
  for (const sim::Primitive& primitive : scene_.primitives) {
    if (primitive.point_class == PointClass::kGround) continue;
    const OrientedBox solid{primitive.center, primitive.rotation(), primitive.size / 2};
    if (!intersects(body, solid)) continue;
    if (primitive.shape == sim::Shape::kCylinder && !intersects(body, turnedAboutAxis(solid)))
      continue;
    return false;
  }
  return true;
}

bool RobotFit::fitsAnyOrientation(const sim::RobotBox& robot, const Eigen::Vector3d& center,
                                  int orientations) const {
  for (int k = 0; k < orientations; ++k)
    if (fits(robot, center, std::numbers::pi * k / orientations)) return true;
  return false;
}

}  // namespace clearway::eval
