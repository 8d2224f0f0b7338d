// A file like Hannover's, built by hand (no real data): the origin on the ground, fans run
// together in the file, a fan passing over something near, a turntable that overran. The floor
// must come out observed all round, as on the real scans (real_field_test.cpp).

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include "clearway/pipeline.h"
#include "clearway/scan.h"
#include "clearway/traversability/traversability_map.h"

namespace clearway {
namespace {

// A full turn of 180 vertical fans from a scanner 0.8 m above an open floor ringed by a wall
// 16 m away, written as the Hannover files are: the origin on the floor (every floor point at
// elevation zero from it), four fans to a line (no jump in elevation from the origin to split
// them at), one return in ten lost, and each fan going up the wall as far as it happens to see
// (a tree, a facade): lines of different lengths. The floor between 2 m and 6 m from the axis must
// be observed ground all round, not cut into strips between fans that were paired wrongly.
TEST(GroundLevelOrigin, FansRunTogetherInTheFileStillJoinTheirFloor) {
  constexpr int kFans = 180, kFansPerLine = 4;
  constexpr double kScannerHeight = 0.8, kWallRange = 16.0, kDeg = std::numbers::pi / 180.0;
  std::mt19937 random(14);
  std::bernoulli_distribution lost(0.1);
  std::uniform_int_distribution<int> up_the_wall(0, 60);  // returns, 0.5 deg apart
  Scan scan;
  auto add = [&](double beta, double range, double z) {
    if (lost(random)) return;
    scan.points.push_back({float(std::cos(beta) * range), float(std::sin(beta) * range), float(z)});
    scan.status.push_back(PointStatus::kValid);
    ++scan.lines.back().count;
  };
  for (int f = 0; f < kFans; ++f) {
    if (f % kFansPerLine == 0) scan.lines.push_back({scan.points.size(), 0});
    const double beta = 2.0 * std::numbers::pi * f / kFans;
    // Down to the floor from 60 deg below the horizon to where it meets the wall, 0.5 deg apart.
    double elevation = -60.0;
    for (; kScannerHeight / std::tan(-elevation * kDeg) < kWallRange; elevation += 0.5)
      add(beta, kScannerHeight / std::tan(-elevation * kDeg), 0.0);
    for (int k = up_the_wall(random); k > 0; --k, elevation += 0.5)
      add(beta, kWallRange, kScannerHeight + kWallRange * std::tan(elevation * kDeg));
  }
  scan.sensor_pose = SensorPose{};
  scan.pose_source = PoseSource::kFile;
  const PipelineResult result = runPipeline(scan, SegmentationParams{});
  ASSERT_TRUE(result.trusted()) << result.analysis->reason;
  const TraversabilityMap& map = result.map;
  std::size_t annulus = 0, unobserved = 0;
  for (int row = 0; row < map.grid.height; ++row)
    for (int column = 0; column < map.grid.width; ++column) {
      const double distance = map.grid.centre(column, row).norm();
      if (distance < 2.0 || distance > 6.0) continue;
      ++annulus;
      unobserved += map.label(column, row) == CellLabel::kUnknown;
    }
  EXPECT_GT(annulus, 1000u);
  EXPECT_LT(double(unobserved), 0.01 * double(annulus)) << unobserved << " of " << annulus;
}

// A turn of vertical fans from a scanner kGroundOriginScannerHeight above an open floor ringed by a
// wall kWallRange away, written with the origin on the floor as Hannover's files are, one fan to a
// line. `fan(k)` says where fan k points (its angle) and what it sees: the floor from
// `floor_from` metres out, and optionally a box in front of the wall.
struct GroundOriginFan {
  double beta = 0.0;        // turntable angle [rad]
  double floor_from = 0.0;  // the first floor return's range [m] (the file began mid-fan)
  bool box = false;         // a box's face in front of the wall (kBoxRange, kBoxHeight)
  int keep_one_in = 1;      // every n-th return kept (a faster turn's sparser fans)
};

constexpr double kGroundOriginScannerHeight = 1.0, kGroundOriginWallRange = 16.0;
constexpr double kBoxRange = 2.0, kBoxHeight = 1.4;

Scan groundOriginTurn(const std::vector<GroundOriginFan>& fans) {
  constexpr double kDeg = std::numbers::pi / 180.0, kH = kGroundOriginScannerHeight;
  std::mt19937 random(14);
  std::bernoulli_distribution lost(0.1);  // one return in ten: lines of different lengths
  Scan scan;
  for (const GroundOriginFan& fan : fans) {
    scan.lines.push_back({scan.points.size(), 0});
    int index = 0;
    auto add = [&](double range, double z) {
      if (index++ % fan.keep_one_in != 0 || lost(random)) return;
      scan.points.push_back(
          {float(std::cos(fan.beta) * range), float(std::sin(fan.beta) * range), float(z)});
      scan.status.push_back(PointStatus::kValid);
      ++scan.lines.back().count;
    };
    // 0.5 deg apart from 60 deg below the horizon: the floor, the box's face, then the wall up to
    // 75 deg (over the box, the wall seen from the origin lower than the box's top: a drop in
    // elevation to a farther return).
    for (double elevation = -60.0; elevation <= 75.0; elevation += 0.5) {
      const double t = std::tan(elevation * kDeg);
      const double on_floor = elevation < 0.0 ? kH / -t : kGroundOriginWallRange;
      const double at_box = kH + kBoxRange * t;
      if (fan.box && (on_floor > kBoxRange || elevation >= 0.0) && at_box >= 0.0 &&
          at_box <= kBoxHeight) {
        add(kBoxRange, at_box);
      } else if (elevation < 0.0 && on_floor < kGroundOriginWallRange) {
        if (on_floor >= fan.floor_from) add(on_floor, 0.0);
      } else {
        add(kGroundOriginWallRange, kH + kGroundOriginWallRange * t);
      }
    }
  }
  scan.sensor_pose = SensorPose{};
  scan.pose_source = PoseSource::kFile;
  return scan;
}

// Cells without observed ground at `from`-`to` metres from the axis and between the angles
// [deg] `low_deg` and `high_deg`, and how many cells lie there.
std::pair<std::size_t, std::size_t> unobservedIn(const TraversabilityMap& map, double from,
                                                 double to, double low_deg, double high_deg) {
  const double low = low_deg * std::numbers::pi / 180.0, high = high_deg * std::numbers::pi / 180.0;
  std::size_t cells = 0, unobserved = 0;
  for (int row = 0; row < map.grid.height; ++row)
    for (int column = 0; column < map.grid.width; ++column) {
      const Eigen::Vector2d centre = map.grid.centre(column, row);
      const double distance = centre.norm(), angle = std::atan2(centre.y(), centre.x());
      if (distance < from || distance > to || angle < low || angle > high) continue;
      ++cells;
      unobserved += map.label(column, row) == CellLabel::kUnknown;
    }
  return {unobserved, cells};
}

// A fan that passes over the top of a box and hits the wall beyond drops in elevation as seen
// from an origin on the floor. It is still one fan: split there, its upper part sorted between
// the neighbouring fans and left the floor in front of the boxes unobserved in strips.
TEST(GroundLevelOrigin, AFanPassingOverSomethingNearStaysOneFan) {
  constexpr int kFans = 90;  // 4 deg apart: strips wider than the holes the map closes
  std::vector<GroundOriginFan> fans;
  for (int f = 0; f < kFans; ++f) {
    GroundOriginFan fan;
    fan.beta = 2.0 * std::numbers::pi * f / kFans;
    fan.box = f >= 10 && f < 30;  // boxes from 40 to 120 deg
    fans.push_back(fan);
  }
  const PipelineResult result = runPipeline(groundOriginTurn(fans), SegmentationParams{});
  ASSERT_TRUE(result.trusted()) << result.analysis->reason;
  const auto [unobserved, cells] = unobservedIn(result.map, 1.0, 1.9, 50.0, 110.0);
  EXPECT_GT(cells, 300u);
  EXPECT_LT(double(unobserved), 0.02 * double(cells)) << unobserved << " of " << cells;
}

// A turn that overran: its first fans were cut short where the file began (no floor nearer than
// 3 m), the overrun's fans are whole but sparser. Over the whole overlap the first pass has more
// ground, but where its fans were cut short the floor is the overrun's: kept per stretch, not
// for the whole overlap at once.
TEST(GroundLevelOrigin, AnOverrunKeepsTheFloorWhereTheFirstFansWereCutShort) {
  constexpr int kFans = 180, kOverrun = 24, kCutShort = 8;
  std::vector<GroundOriginFan> fans;
  for (int f = 0; f < kFans + kOverrun; ++f) {
    GroundOriginFan fan;
    // The overrun a third of a step off the first pass's angles.
    fan.beta = 2.0 * std::numbers::pi * (f + (f >= kFans ? 1.0 / 3.0 : 0.0)) / kFans;
    if (f < kCutShort) fan.floor_from = 3.0;
    if (f >= kFans) fan.keep_one_in = 2;
    fans.push_back(fan);
  }
  const PipelineResult result = runPipeline(groundOriginTurn(fans), SegmentationParams{});
  ASSERT_TRUE(result.trusted()) << result.analysis->reason;
  // The sector of the cut-short fans, a fan's step in from its ends.
  const auto [unobserved, cells] = unobservedIn(result.map, 1.0, 2.7, 2.0, 14.0);
  EXPECT_GT(cells, 100u);
  EXPECT_LT(double(unobserved), 0.05 * double(cells)) << unobserved << " of " << cells;
}

}  // namespace
}  // namespace clearway
