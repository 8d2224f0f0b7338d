#include "clearway/point_class.h"

#include <array>

namespace clearway {

namespace {
constexpr std::array<std::string_view, kPointClassCount> kNames = {"none",    "ground",   "wall",
                                                                   "ceiling", "obstacle", "stairs"};
}

std::string_view className(PointClass point_class) {
  const auto index = static_cast<std::size_t>(point_class);
  return index < kNames.size() ? kNames[index] : "invalid";
}

std::optional<PointClass> classFromName(std::string_view name) {
  for (std::size_t i = 0; i < kNames.size(); ++i)
    if (kNames[i] == name) return static_cast<PointClass>(i);
  return std::nullopt;
}

}  // namespace clearway
