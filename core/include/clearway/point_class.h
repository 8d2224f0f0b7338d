#pragma once

// What a point or a surface is, shared by the simulator's ground truth and the segmentation.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace clearway {

enum class PointClass : std::uint8_t {
  kNone = 0,  // no return, or not assigned
  kGround = 1,
  kWall = 2,
  kCeiling = 3,
  kObstacle = 4,
  kStairs = 5,
};
inline constexpr int kPointClassCount = 6;

std::string_view className(PointClass point_class);
std::optional<PointClass> classFromName(std::string_view name);

}  // namespace clearway
