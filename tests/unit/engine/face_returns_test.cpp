// Returns on a low box's face that lie in the floor plane's band are the face, not the floor
// (core/src/segmentation/face_returns.h): one scan line comes down the box's face, its last
// returns a few centimetres up and taken into the floor's plane, then runs on over the floor.

#include <gtest/gtest.h>

#include <algorithm>
#include <utility>
#include <vector>

#include "../../../core/src/segmentation/face_returns.h"

namespace clearway {
namespace {

// One scan line over the floor plane h = 0 along x: map heights of its returns, which of them
// the planes took for ground (plane 0, else -1), `spacing` apart.
struct Line {
  std::vector<float> heights;
  std::vector<std::int32_t> ground_of;
  Scan scan;
  std::vector<Eigen::Vector3f> mapped;

  Line(std::vector<float> heights_, std::vector<std::int32_t> ground_of_, float spacing = 0.015F)
      : heights(std::move(heights_)), ground_of(std::move(ground_of_)) {
    for (std::size_t i = 0; i < heights.size(); ++i) {
      scan.points.push_back({float(i) * spacing, 0.0F, heights[i]});
      scan.status.push_back(PointStatus::kValid);
      mapped.emplace_back(float(i) * spacing, 0.0F, heights[i]);
    }
    scan.lines = {{0, heights.size()}};
  }
};

// A box's face (not ground) from 0.12 m down to 0.055 m, then its foot in the floor's band
// (noisy: 0.047, 0.033, 0.048, 0.04), then the floor (within noise of 0).
Line grazedFace(float spacing = 0.015F) {
  return Line(
      {0.12F, 0.09F, 0.07F, 0.055F, 0.047F, 0.033F, 0.048F, 0.04F, 0.012F, 0.004F, 0.015F, 0.0F},
      {-1, -1, -1, -1, 0, 0, 0, 0, 0, 0, 0, 0}, spacing);
}

const std::vector<Eigen::Vector3d> kFloorAtZero = {Eigen::Vector3d::Zero()};  // h = 0 everywhere

TEST(FaceReturns, TheFacesFootInTheFloorsBandIsNotGround) {
  const Line line = grazedFace();
  std::vector<std::int32_t> ground_of = line.ground_of;
  EXPECT_EQ(detail::dropFaceReturns(ground_of, line.scan, line.mapped, kFloorAtZero), 4u);
  for (std::size_t i = 4; i < 8; ++i)
    EXPECT_EQ(ground_of[i], -1) << "return " << i << " at " << line.heights[i] << " m";
  for (std::size_t i = 8; i < ground_of.size(); ++i)
    EXPECT_EQ(ground_of[i], 0) << "floor return " << i;
}

// The same line in reverse order: the walk goes both ways.
TEST(FaceReturns, EitherWayAlongTheLine) {
  Line line = grazedFace();
  std::reverse(line.scan.points.begin(), line.scan.points.end());
  std::reverse(line.mapped.begin(), line.mapped.end());
  std::vector<std::int32_t> ground_of(line.ground_of.rbegin(), line.ground_of.rend());
  EXPECT_EQ(detail::dropFaceReturns(ground_of, line.scan, line.mapped, kFloorAtZero), 4u);
}

// Returns farther apart than the face's reach are not one face: the floor is floor, however
// noisy, after an obstacle return 0.2 m away.
TEST(FaceReturns, ReturnsFarFromTheObstacleStayGround) {
  const Line line = grazedFace(0.2F);
  std::vector<std::int32_t> ground_of = line.ground_of;
  EXPECT_EQ(detail::dropFaceReturns(ground_of, line.scan, line.mapped, kFloorAtZero), 0u);
  EXPECT_EQ(ground_of, line.ground_of);
}

// A floor return within noise of its plane beside a wall's foot stays ground: a door's width is
// measured to its jambs' faces, and the floor in front of them is floor.
TEST(FaceReturns, FloorNoiseBesideAWallStaysGround) {
  const Line wall({1.0F, 0.6F, 0.3F, 0.1F, 0.018F, 0.006F, 0.012F, 0.0F},
                  {-1, -1, -1, -1, 0, 0, 0, 0});
  std::vector<std::int32_t> ground_of = wall.ground_of;
  EXPECT_EQ(detail::dropFaceReturns(ground_of, wall.scan, wall.mapped, kFloorAtZero), 0u);
}

}  // namespace
}  // namespace clearway
