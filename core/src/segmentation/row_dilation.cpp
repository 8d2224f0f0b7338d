#include "row_dilation.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

namespace clearway::detail {
namespace {

constexpr std::uint16_t kFar = std::numeric_limits<std::uint16_t>::max();
constexpr std::uint8_t kSet = 255;

// Per element row, the half-width of its run about the middle column (-1 for an empty row), or
// nothing when a row is not such a run.
std::optional<std::vector<int>> centredHalfWidths(const cv::Mat& element) {
  if (element.type() != CV_8UC1 || element.rows % 2 == 0 || element.cols % 2 == 0) return {};
  const int middle = element.cols / 2;
  std::vector<int> half_widths(std::size_t(element.rows), -1);
  for (int row = 0; row < element.rows; ++row) {
    const std::uint8_t* cells = element.ptr<std::uint8_t>(row);
    int first = -1, last = -1, count = 0;
    for (int column = 0; column < element.cols; ++column) {
      if (!cells[column]) continue;
      if (first < 0) first = column;
      last = column;
      ++count;
    }
    if (count == 0) continue;
    if (count != last - first + 1 || middle - first != last - middle) return {};
    half_widths[std::size_t(row)] = middle - first;
  }
  return half_widths;
}

// Each pixel's distance along its row to the nearest set pixel of that row (kFar if none).
void rowDistances(const cv::Mat& mask, std::vector<std::uint16_t>& distances) {
  const auto width = std::size_t(mask.cols);
  distances.assign(std::size_t(mask.rows) * width, kFar);
  for (int row = 0; row < mask.rows; ++row) {
    const std::uint8_t* in = mask.ptr<std::uint8_t>(row);
    std::uint16_t* out = distances.data() + std::size_t(row) * width;
    std::uint16_t running = kFar;
    for (std::size_t x = 0; x < width; ++x) {
      running = in[x] ? 0 : (running == kFar ? kFar : std::uint16_t(running + 1));
      out[x] = running;
    }
    running = kFar;
    for (std::size_t x = width; x-- > 0;) {
      running = in[x] ? 0 : (running == kFar ? kFar : std::uint16_t(running + 1));
      out[x] = std::min(out[x], running);
    }
  }
}

}  // namespace

void dilateByCentredRows(const cv::Mat& mask, cv::Mat& out, const cv::Mat& element) {
  const std::optional<std::vector<int>> half_widths = centredHalfWidths(element);
  if (!half_widths || mask.type() != CV_8UC1 || mask.cols >= int(kFar)) {
    cv::dilate(mask, out, element);
    return;
  }
  std::vector<std::uint16_t> distances;
  rowDistances(mask, distances);
  const auto width = std::size_t(mask.cols);
  const int reach = element.rows / 2;
  cv::Mat result(mask.rows, mask.cols, CV_8UC1);
  std::vector<std::uint8_t> any(width);
  for (int row = 0; row < mask.rows; ++row) {
    std::fill(any.begin(), any.end(), std::uint8_t{0});
    for (int offset = -reach; offset <= reach; ++offset) {
      const int half_width = (*half_widths)[std::size_t(offset + reach)];
      const int source = row + offset;
      if (half_width < 0 || source < 0 || source >= mask.rows) continue;
      const std::uint16_t* near = distances.data() + std::size_t(source) * width;
      const auto limit = std::uint16_t(half_width);
      for (std::size_t x = 0; x < width; ++x)
        any[x] |= std::uint8_t(near[x] <= limit);
    }
    std::uint8_t* cells = result.ptr<std::uint8_t>(row);
    for (std::size_t x = 0; x < width; ++x)
      cells[x] = any[x] ? kSet : 0;
  }
  out = result;
}

}  // namespace clearway::detail
