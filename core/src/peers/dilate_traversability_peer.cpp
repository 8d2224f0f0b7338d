#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>

#include "clearway/peers/traversability_peer.h"
#include "traversability/cell_classes.h"

namespace clearway::peers {
namespace {

// The robot's footprint turned by `yaw` as a structuring element: the cells whose centres lie in
// the box centred on the kernel's middle cell.
cv::Mat footprintKernel(const RobotParams& robot, double resolution, double yaw) {
  const double along = robot.length / 2 / resolution, across = robot.width / 2 / resolution;
  const int radius = int(std::ceil(std::hypot(along, across)));
  cv::Mat kernel(2 * radius + 1, 2 * radius + 1, CV_8UC1, cv::Scalar(0));
  const double c = std::cos(yaw), s = std::sin(yaw);
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx)
      if (std::abs(dx * c + dy * s) <= along && std::abs(-dx * s + dy * c) <= across)
        kernel.at<std::uint8_t>(dy + radius, dx + radius) = 1;
  return kernel;
}

}  // namespace

std::vector<std::uint8_t> dilateTraversability(const ScanAnalysis& analysis,
                                               const RobotParams& robot, const MapParams& params,
                                               const std::vector<double>& yaws, int threads) {
  const MapGrid& grid = analysis.inputs.grid;
  std::vector<std::uint8_t> labels(grid.cells(), 0);
  if (!analysis.ground_found || grid.cells() == 0) return labels;
  // OpenCV's thread count is process-wide: use the caller's for this call only.
  const int opencv_threads = cv::getNumThreads();
  cv::setNumThreads(threads);
  MapParams grid_params = params;
  grid_params.resolution = grid.resolution;
  const detail::CellClasses classes = detail::classifyCells(analysis, robot, grid_params);

  // 255 where the robot may not put any part of its box: blocked or never observed.
  cv::Mat occupied(grid.height, grid.width, CV_8UC1);
  for (int row = 0; row < grid.height; ++row)
    for (int column = 0; column < grid.width; ++column) {
      const detail::CellState state = classes.state[grid.index(column, row)];
      occupied.at<std::uint8_t>(row, column) =
          state == detail::CellState::kGround || state == detail::CellState::kLowObstacle ? 0 : 255;
    }
  cv::Mat fits_somehow(grid.height, grid.width, CV_8UC1, cv::Scalar(0));
  cv::Mat swept;
  for (const double yaw : yaws) {
    cv::dilate(occupied, swept, footprintKernel(robot, grid.resolution, yaw), cv::Point(-1, -1), 1,
               cv::BORDER_CONSTANT, cv::Scalar(255));
    fits_somehow.setTo(255, swept == 0);
  }
  cv::setNumThreads(opencv_threads);
  for (int row = 0; row < grid.height; ++row)
    for (int column = 0; column < grid.width; ++column) {
      const std::size_t cell = grid.index(column, row);
      if (classes.state[cell] == detail::CellState::kUnknown) continue;
      labels[cell] = fits_somehow.at<std::uint8_t>(row, column) ? 1 : 4;
    }
  return labels;
}

}  // namespace clearway::peers
