// Ground followed outward ring by ring (core/src/segmentation/ring_ground.h): three rings of a
// head 1.73 m above a flat road, 9.8, 19.8 and 33 m out, one return per degree of azimuth; the
// nearest ring is on the road plane, the farther ones on no plane yet.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "../../../core/src/segmentation/ring_ground.h"
#include "../../../core/src/segmentation/ring_support.h"

namespace clearway {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kHeight = 1.73;  // [m] the head above the road
constexpr int kAzimuths = 360;

struct Rings {
  Scan scan;
  std::vector<std::int32_t> point_plane;
  std::vector<Plane> planes;
  // The return of ring r at azimuth a (degrees).
  static std::size_t index(int ring, int azimuth) {
    return std::size_t(ring * kAzimuths + azimuth);
  }
};

// `raise(ring, azimuth)`: how far above the road that return lies [m].
template <typename Raise>
Rings rings(Raise&& raise) {
  Rings r;
  const double elevations[] = {-10.0, -5.0, -3.0};
  for (int ring = 0; ring < 3; ++ring) {
    const ScanLine line{r.scan.points.size(), std::size_t(kAzimuths)};
    const double distance = kHeight / std::tan(-elevations[ring] * kDeg);
    for (int a = 0; a < kAzimuths; ++a) {
      const double z = -kHeight + raise(ring, a);
      r.scan.points.push_back(
          {float(distance * std::cos(a * kDeg)), float(distance * std::sin(a * kDeg)), float(z)});
      r.scan.status.push_back(PointStatus::kValid);
      r.point_plane.push_back(ring == 0 ? 0 : -1);
    }
    r.scan.lines.push_back(line);
  }
  Plane road;
  road.normal = -Eigen::Vector3d::UnitZ();  // from the head towards the road
  road.offset = kHeight;
  Plane wall;
  wall.normal = Eigen::Vector3d::UnitX();
  wall.offset = 50.0;
  r.planes = {road, wall};
  return r;
}

// Each return's facing one on the next ring up, one degree of azimuth apart.
detail::RingLayout layoutOf(const Scan& scan) {
  return detail::ringLayout(scan, {0, 1, 2}, 1.0 * kDeg, 1);
}

std::size_t follow(Rings& r) {
  detail::OutwardGroundLimits limits;
  limits.off_plane = 0.1;    // the robot's step
  limits.per_metre = 0.005;  // 0.1 + 0.165 m at 33 m
  limits.max_slope = 1.0;    // 45 deg
  return detail::followGroundOutward(r.scan, {0, 1, 2}, layoutOf(r.scan), r.planes, {0}, limits,
                                     r.point_plane);
}

TEST(OutwardGround, FarRingsOnTheRoadJoinItsPlane) {
  Rings r = rings([](int, int a) { return 0.01 * std::sin(a * kDeg * 7.0); });  // 1 cm noise
  EXPECT_EQ(follow(r), std::size_t(2 * kAzimuths));
  for (std::size_t i = 0; i < r.point_plane.size(); ++i)
    EXPECT_EQ(r.point_plane[i], 0) << i;
}

// A hedge's top 1 m up on the middle ring stays off the road, and so does the road beyond it: the
// outer ring there faces no ground. A kerb-high rise (5 cm) at 33 m joins; 0.3 m there does not
// (more than the step and the range's share of noise).
TEST(OutwardGround, WhatStandsAboveTheStepStaysOffAndHidesWhatLiesBeyond) {
  Rings r = rings([](int ring, int a) {
    if (ring == 1 && a >= 90 && a < 120) return 1.0;
    if (ring == 2 && a >= 200 && a < 210) return 0.3;
    if (ring == 2 && a >= 300 && a < 310) return 0.05;
    return 0.0;
  });
  follow(r);
  for (int a = 0; a < kAzimuths; ++a) {
    const bool hedge = a >= 90 && a < 120;
    EXPECT_EQ(r.point_plane[Rings::index(1, a)], hedge ? -1 : 0) << a;
    const bool off = hedge || (a >= 200 && a < 210);
    EXPECT_EQ(r.point_plane[Rings::index(2, a)], off ? -1 : 0) << a;
  }
}

// A return already on another plane (a wall's foot) keeps it; a rise steeper than the robot drives
// from the return it follows (a short hop up within the band) does not join.
TEST(OutwardGround, ReturnsOnOtherPlanesKeepThemAndSteepRisesStayOff) {
  Rings r = rings([](int, int) { return 0.0; });
  r.point_plane[Rings::index(1, 10)] = 1;
  follow(r);
  EXPECT_EQ(r.point_plane[Rings::index(1, 10)], 1);

  // The middle ring pulled in to 0.1 m beyond the nearest and 0.09 m up: within the step of the
  // plane, but 42 deg of rise over 0.1 m with a slope limit of 0.5 (27 deg) is a face.
  Rings steep = rings([](int, int) { return 0.0; });
  for (int a = 0; a < kAzimuths; ++a) {
    Point3f& p = steep.scan.points[Rings::index(1, a)];
    const double distance = kHeight / std::tan(10.0 * kDeg) + 0.1;
    p = {float(distance * std::cos(a * kDeg)), float(distance * std::sin(a * kDeg)),
         float(-kHeight + 0.09)};
  }
  detail::OutwardGroundLimits limits;
  limits.off_plane = 0.1;
  limits.max_slope = 0.5;
  limits.noise = 0.02;
  detail::followGroundOutward(steep.scan, {0, 1, 2}, layoutOf(steep.scan), steep.planes, {0},
                              limits, steep.point_plane);
  for (int a = 0; a < kAzimuths; ++a)
    EXPECT_EQ(steep.point_plane[Rings::index(1, a)], -1) << a;
}

}  // namespace
}  // namespace clearway
