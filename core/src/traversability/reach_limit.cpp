#include "reach_limit.h"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <utility>
#include <vector>

namespace clearway::detail {
namespace {

// The cause worth naming is the one of more than this share of the causes around the reach.
constexpr double kMostOf = 0.5;

std::string percent(std::size_t part, std::size_t whole) {
  const double share = double(part) / double(std::max<std::size_t>(whole, 1));
  return std::to_string(int(std::lround(100.0 * share))) + " %";
}

// Whole centimetres below a metre: "0.0 m away" read as a contradiction.
// Cells this near the robot's place lie beside it.
constexpr double kBesideCells = 1.5;

std::string metres(double value) {
  char text[32];
  std::snprintf(text, sizeof text, value < 1.0 ? "%.2f m" : "%.1f m", value);
  return text;
}

}  // namespace

std::string describeReachLimit(const TraversabilityMap& map, double box_reach_cells) {
  const MapGrid& grid = map.grid;
  if (map.reachable_cells == 0 || map.fits_not_reachable_cells <= map.reachable_cells ||
      map.reach.size() != grid.cells())
    return {};
  // The nearest cell where the box fits but that the search did not reach, and the reach's
  // bounding box of cells.
  double nearest_fit = std::numeric_limits<double>::infinity();
  const Eigen::Vector2d robot(map.robot_pose.x, map.robot_pose.y);
  int first_row = grid.height, last_row = -1, first_column = grid.width, last_column = -1;
  for (int row = 0; row < grid.height; ++row)
    for (int column = 0; column < grid.width; ++column) {
      const std::size_t cell = grid.index(column, row);
      if (map.reach[cell]) {
        first_row = std::min(first_row, row);
        last_row = row;
        first_column = std::min(first_column, column);
        last_column = std::max(last_column, column);
      } else if (robotFits(CellLabel(map.labels[cell]))) {
        nearest_fit = std::min(nearest_fit, (grid.centre(column, row) - robot).norm());
      }
    }
  // Each cell's distance to the reach, in the window of cells within the box's reach of it (the
  // reach of a robot that is stuck is small: no pass over the whole map).
  const int margin = int(std::ceil(box_reach_cells)) + 1;
  const cv::Rect window =
      cv::Rect(first_column - margin, first_row - margin,
               last_column - first_column + 1 + 2 * margin, last_row - first_row + 1 + 2 * margin) &
      cv::Rect(0, 0, grid.width, grid.height);
  cv::Mat outside(window.height, window.width, CV_8UC1);
  for (int y = 0; y < window.height; ++y)
    for (int x = 0; x < window.width; ++x)
      outside.at<std::uint8_t>(y, x) = map.reach[grid.index(window.x + x, window.y + y)] ? 0 : 1;
  cv::Mat distance;
  cv::distanceTransform(outside, distance, cv::DIST_L2, cv::DIST_MASK_5);
  // What stops the box just beyond the reach lies within its reach of a reached cell: unobserved
  // cells, or cells that block for a reason of their own (a wall, an overhang, a step, stairs).
  // Free cells where the box does not fit are not a cause: something of those is near them.
  std::size_t causes = 0, unobserved = 0, stairs = 0;
  std::array<std::size_t, 9> blocked_by{};  // per CellReason
  for (int y = 0; y < window.height; ++y)
    for (int x = 0; x < window.width; ++x) {
      const std::size_t cell = grid.index(window.x + x, window.y + y);
      const auto label = CellLabel(map.labels[cell]);
      if (map.reach[cell] || robotFits(label) || distance.at<float>(y, x) > box_reach_cells)
        continue;
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
  // Within a cell or so of its own place: it fits right there, so turning or driving off the
  // spot is what fails, and the distance alone would not say so.
  if (std::isfinite(nearest_fit) && nearest_fit <= kBesideCells * grid.resolution)
    text += "; it fits right beside its own place (" + metres(nearest_fit) +
            " away) but cannot turn or drive there";
  else if (std::isfinite(nearest_fit))
    text += "; the nearest such cell is " + metres(nearest_fit) + " away";
  return text;
}

}  // namespace clearway::detail
