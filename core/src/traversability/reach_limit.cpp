#include "reach_limit.h"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace clearway::detail {
namespace {

bool fits(CellLabel label) {
  return label == CellLabel::kTraversable || label == CellLabel::kCareful ||
         label == CellLabel::kObstacle;
}

// The cause worth naming is the one of more than this share of the causes around the reach.
constexpr double kMostOf = 0.5;

std::string percent(std::size_t part, std::size_t whole) {
  const double share = double(part) / double(std::max<std::size_t>(whole, 1));
  return std::to_string(int(std::lround(100.0 * share))) + " %";
}

std::string metres(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f m", value);
  return text;
}

}  // namespace

std::string describeReachLimit(const TraversabilityMap& map, double box_reach_cells) {
  const MapGrid& grid = map.grid;
  if (map.reachable_cells == 0 || map.fits_not_reachable_cells <= map.reachable_cells ||
      map.reach.size() != grid.cells())
    return {};
  // Each cell's distance to the reach (rows of the grid are rows of the image).
  std::vector<std::uint8_t> outside(grid.cells());
  std::transform(map.reach.begin(), map.reach.end(), outside.begin(),
                 [](std::uint8_t reached) { return std::uint8_t(reached ? 0 : 1); });
  const cv::Mat outside_image(grid.height, grid.width, CV_8UC1, outside.data());
  cv::Mat distance;
  cv::distanceTransform(outside_image, distance, cv::DIST_L2, cv::DIST_MASK_5);
  // What stops the box just beyond the reach lies within its reach of a reached cell: unobserved
  // cells, or cells that block for a reason of their own (a wall, an overhang, a step, stairs).
  // Free cells where the box does not fit are not a cause: something of those is near them.
  std::size_t causes = 0, unobserved = 0, stairs = 0;
  std::array<std::size_t, 8> blocked_by{};  // per CellReason
  double nearest_fit = std::numeric_limits<double>::infinity();
  const Eigen::Vector2d robot(map.robot_pose.x, map.robot_pose.y);
  for (int row = 0; row < grid.height; ++row) {
    const float* away = distance.ptr<float>(row);
    for (int column = 0; column < grid.width; ++column) {
      const std::size_t cell = grid.index(column, row);
      if (map.reach[cell]) continue;
      const CellLabel label = map.label(column, row);
      if (fits(label)) {
        nearest_fit = std::min(nearest_fit, (grid.centre(column, row) - robot).norm());
        continue;
      }
      if (away[column] > box_reach_cells) continue;
      if (label == CellLabel::kUnknown) {
        ++unobserved;
      } else if (label == CellLabel::kStairs) {
        ++stairs;
      } else {
        const auto reason = CellReason(map.reasons[cell]);
        if (reason == CellReason::kTooNarrow) continue;
        ++blocked_by[std::min<std::size_t>(std::size_t(reason), blocked_by.size() - 1)];
      }
      ++causes;
    }
  }
  const std::size_t reached = map.reachable_cells;
  std::string text = "the robot reaches " + std::to_string(reached) +
                     (reached == 1 ? " cell" : " cells") + " from its own place and fits in " +
                     std::to_string(map.fits_not_reachable_cells) + " more it cannot get to";
  // The causes, largest first.
  std::vector<std::pair<std::size_t, std::string>> named = {{unobserved, "unobserved ground"},
                                                            {stairs, "stairs"}};
  for (std::size_t reason = 1; reason < blocked_by.size(); ++reason)
    named.emplace_back(blocked_by[reason], std::string(reasonName(CellReason(reason))));
  std::stable_sort(named.begin(), named.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  if (causes == 0) {
    // Nothing blocks around it but the box's own fit: turning or squeezing is what fails.
  } else if (named[0].first == unobserved && double(unobserved) > kMostOf * double(causes)) {
    text += ": the ground around it was not seen (" + percent(unobserved, causes) +
            " of what stops it is unobserved ground: the scanner's blind zone around the robot, "
            "or what its own body hid)";
  } else if (double(named[0].first) > kMostOf * double(causes)) {
    text += ": it is shut in (" + percent(named[0].first, causes) + " of what stops it is " +
            named[0].second + ")";
  } else {
    text += ": what stops it is " + named[0].second + " (" + percent(named[0].first, causes) +
            ") and " + named[1].second + " (" + percent(named[1].first, causes) + ")";
  }
  if (std::isfinite(nearest_fit))
    text += "; the nearest such cell is " + metres(nearest_fit) + " away";
  return text;
}

}  // namespace clearway::detail
