#include "distance_field.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace clearway::detail {
namespace {

// The squared distances of the cells strictly between two blocking cells `first` and `last` of a
// row: out[x] = min over first <= x' <= last of (x - x')^2 + f[x'], where f[x'] is the squared
// distance from cell x' to the nearest blocking cell of its own column (0 at first and last). A
// cell beyond a blocking cell of the row is never nearer than that cell, so each stretch of free
// cells is its own problem. `site` and `start` are scratch for the lower envelope of the
// parabolas, of at least last - first + 1 entries.
void envelopeBetween(const double* f, int first, int last, double* out, int* site, double* start) {
  // Where the parabola of x comes below the one of site s (s < x), and stays below.
  auto crossing = [f](int s, int x) {
    return ((f[x] + double(x) * x) - (f[s] + double(s) * s)) / (2.0 * (x - s));
  };
  int top = 0;
  site[0] = first;
  start[0] = first;  // the lower envelope is only read from first on
  for (int x = first + 1; x <= last; ++x) {
    double from = crossing(site[top], x);
    while (top > 0 && from <= start[top]) {
      --top;
      from = crossing(site[top], x);
    }
    ++top;
    site[top] = x;
    start[top] = from;
  }
  int k = 0;
  for (int x = first + 1; x < last; ++x) {
    while (k < top && start[k + 1] <= x)
      ++k;
    const double along = x - site[k];
    out[x] = along * along + f[site[k]];
  }
}

}  // namespace

std::vector<float> distanceToBlocked(const std::vector<std::uint8_t>& free, int width, int height) {
  const auto w = std::size_t(width), h = std::size_t(height);
  // Down each column, rows at a time (the grid is row-major): cells to the nearest blocking cell
  // above, then below, the rows outside the grid blocking.
  std::vector<int> vertical(w * h);
  for (std::size_t row = 0; row < h; ++row)
    for (std::size_t column = 0; column < w; ++column) {
      const std::size_t cell = row * w + column;
      const int above = row == 0 ? 0 : vertical[cell - w];
      vertical[cell] = free[cell] ? above + 1 : 0;
    }
  for (std::size_t row = h; row-- > 0;)
    for (std::size_t column = 0; column < w; ++column) {
      const std::size_t cell = row * w + column;
      const int below = row + 1 == h ? 0 : vertical[cell + w];
      vertical[cell] = std::min(vertical[cell], below + 1);
    }
  // Along each row, padded by one blocking cell at either end (index = column + 1).
  std::vector<float> distance(w * h);
  std::vector<double> squared(w + 2, 0.0), envelope(w + 2, 0.0), start(w + 2);
  std::vector<int> site(w + 2);
  for (std::size_t row = 0; row < h; ++row) {
    const int* column_distance = vertical.data() + row * w;
    for (std::size_t column = 0; column < w; ++column) {
      const double d = column_distance[column];
      squared[column + 1] = d * d;
    }
    int blocking = 0;
    for (int x = 1; x <= int(w) + 1; ++x) {
      if (squared[std::size_t(x)] != 0.0) continue;
      if (x - blocking > 1)
        envelopeBetween(squared.data(), blocking, x, envelope.data(), site.data(), start.data());
      envelope[std::size_t(x)] = 0.0;
      blocking = x;
    }
    float* out = distance.data() + row * w;
    for (std::size_t column = 0; column < w; ++column)
      out[column] = float(std::sqrt(envelope[column + 1]));
  }
  return distance;
}

}  // namespace clearway::detail
