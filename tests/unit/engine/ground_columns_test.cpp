// Ground lies on top of its column (dropGroundOverLowerReturns, built by hand: no pipeline): a
// plane fitted along a face, or over one, is not ground; ground beside a kerb or on a slope the
// robot drives stays ground.

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "clearway/scan.h"
#include "clearway/segmentation/scan_analysis.h"

namespace clearway {
namespace {

constexpr double kStep = 0.1;        // the robot's step [m]
constexpr double kMaxSlopeDeg = 45;  // its steepest slope

// A scan built plane by plane: each added point is given to a plane (or to none, -1).
struct HandBuilt {
  Scan scan;
  ScanAnalysis analysis;

  HandBuilt() {
    analysis.ground_found = true;
    analysis.planes.planes.resize(4);
    for (Plane& plane : analysis.planes.planes)
      plane.kind = PlaneKind::kGround;
    analysis.ground_planes = {0, 1, 2, 3};
    analysis.reference_ground = 0;
  }
  void add(double x, double y, double z, std::int32_t plane) {
    scan.points.push_back({float(x), float(y), float(z)});
    scan.status.push_back(PointStatus::kValid);
    analysis.planes.point_plane.push_back(plane);
  }
  std::size_t pointsOn(std::int32_t plane) const {
    std::size_t count = 0;
    for (const std::int32_t p : analysis.planes.point_plane)
      count += p == plane;
    return count;
  }
};

TEST(GroundColumns, APlaneOverAFaceIsNotGroundAndGroundBesideItStays) {
  HandBuilt built;
  // Plane 0, the road: z = 0 over 0 <= x < 4, 0 <= y < 2, 5 cm apart.
  for (int i = 0; i < 80; ++i)
    for (int j = 0; j < 40; ++j)
      built.add(0.05 * i + 0.025, 0.05 * j + 0.025, 0.0, 0);
  // Plane 1, a hedge's top 1 m up over 2 <= y < 3, its face below it seen through the leaves in
  // most of its columns (returns on no plane, every 0.2 m down).
  for (int i = 0; i < 80; ++i)
    for (int j = 0; j < 20; ++j) {
      const double x = 0.05 * i + 0.025, y = 2.0 + 0.05 * j + 0.025;
      built.add(x, y, 1.0, 1);
      if (j % 4 != 0)
        for (double z = 0.0; z < 0.9; z += 0.2)
          built.add(x, y, z, -1);
    }
  // Plane 2, a pavement a kerb higher (0.12 m) over 4 <= x < 6: nothing under it.
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j)
      built.add(4.0 + 0.05 * i + 0.025, 0.05 * j + 0.025, 0.12, 2);
  // Plane 3, a ramp as steep as the robot drives (45 deg) over -2 <= x < 0, rising towards -x.
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) {
      const double x = -0.05 * i - 0.025;
      built.add(x, 0.05 * j + 0.025, -x, 3);
    }
  const std::size_t road = built.pointsOn(0), pavement = built.pointsOn(2),
                    ramp = built.pointsOn(3);

  // Three threads: the scan's parts find their lowest returns apart, merged after.
  EXPECT_EQ(dropGroundOverLowerReturns(built.scan, kStep, kMaxSlopeDeg, built.analysis, 3), 1u);
  EXPECT_EQ(built.analysis.planes.planes[1].kind, PlaneKind::kOther);
  EXPECT_EQ(built.pointsOn(1), 0u);
  EXPECT_EQ(built.analysis.ground_planes, (std::vector<int>{0, 2, 3}));
  EXPECT_EQ(built.pointsOn(0), road);
  EXPECT_EQ(built.pointsOn(2), pavement);
  EXPECT_EQ(built.pointsOn(3), ramp);
}

TEST(GroundColumns, AReturnUnderTheRoadTakesOnlyTheRoadPointAboveIt) {
  HandBuilt built;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j)
      built.add(0.05 * i + 0.025, 0.05 * j + 0.025, 0.0, 0);
  const std::size_t road = built.pointsOn(0);
  // A return 0.5 m below the road (a reflection in a puddle): the road points in its column are
  // over something lower, so they are no longer ground; the road itself (the reference) stays.
  built.add(1.01, 1.01, -0.5, -1);
  EXPECT_EQ(dropGroundOverLowerReturns(built.scan, kStep, kMaxSlopeDeg, built.analysis), 0u);
  EXPECT_EQ(built.analysis.planes.planes[0].kind, PlaneKind::kGround);
  // A column is 0.1 m wide: at most 3 x 3 of these points, 5 cm apart, share it.
  EXPECT_LT(built.pointsOn(0), road);
  EXPECT_GE(built.pointsOn(0), road - 9);
}

}  // namespace
}  // namespace clearway
