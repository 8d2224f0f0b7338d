#include "distance_field.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace clearway::detail {
namespace {

// The squared distances of the cells strictly between two blocking cells `first` and `last` of a
// row: out[x] = min over first <= x' <= last of (x - x')^2 + f[x'], where f[x'] is the squared
// distance from cell x' to the nearest blocking cell of its own column (0 at first and last). A
// cell beyond a blocking cell of the row is never nearer than that cell, so each stretch of free
// cells is its own problem. `site` and `start_*` are scratch for the lower envelope of the
// parabolas, of at least last - first + 1 entries. All of it is integers: where two parabolas
// cross is a fraction, kept as numerator and denominator and compared by cross-multiplying (no
// division per cell, and no rounding: a grid of a million cells a side stays far inside int64).
void envelopeBetween(const std::int64_t* f, int first, int last, std::int64_t* out, int* site,
                     std::int64_t* start_numerator, std::int64_t* start_denominator) {
  int top = 0;
  site[0] = first;
  start_numerator[0] = first;  // the lower envelope is only read from first on
  start_denominator[0] = 1;
  for (int x = first + 1; x <= last; ++x) {
    // Where the parabola of x comes below the one of site s (s < x), and stays below:
    // ((f[x] + x^2) - (f[s] + s^2)) / (2 (x - s)).
    const std::int64_t own = f[x] + std::int64_t(x) * x;
    auto numerator = [&](int s) { return own - (f[s] + std::int64_t(s) * s); };
    std::int64_t from_numerator = numerator(site[top]);
    std::int64_t from_denominator = 2 * std::int64_t(x - site[top]);
    while (top > 0 &&
           from_numerator * start_denominator[top] <= start_numerator[top] * from_denominator) {
      --top;
      from_numerator = numerator(site[top]);
      from_denominator = 2 * std::int64_t(x - site[top]);
    }
    ++top;
    site[top] = x;
    start_numerator[top] = from_numerator;
    start_denominator[top] = from_denominator;
  }
  int k = 0;
  for (int x = first + 1; x < last; ++x) {
    while (k < top && start_numerator[k + 1] <= std::int64_t(x) * start_denominator[k + 1])
      ++k;
    const std::int64_t along = x - site[k];
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
  std::vector<std::int64_t> squared(w + 2, 0), envelope(w + 2, 0), start_numerator(w + 2),
      start_denominator(w + 2);
  std::vector<int> site(w + 2);
  for (std::size_t row = 0; row < h; ++row) {
    const int* column_distance = vertical.data() + row * w;
    for (std::size_t column = 0; column < w; ++column) {
      const std::int64_t d = column_distance[column];
      squared[column + 1] = d * d;
    }
    int blocking = 0;
    for (int x = 1; x <= int(w) + 1; ++x) {
      if (squared[std::size_t(x)] != 0) continue;
      if (x - blocking > 1)
        envelopeBetween(squared.data(), blocking, x, envelope.data(), site.data(),
                        start_numerator.data(), start_denominator.data());
      envelope[std::size_t(x)] = 0;
      blocking = x;
    }
    // The root of an integer below 2^24 (exact in float) taken in float is the root taken in
    // double rounded to float (double has more than twice float's precision, plus two bits): the
    // same distances, in half the time. Larger ones (cells over 4,000 apart) go through double.
    constexpr std::int64_t kExactInFloat = std::int64_t{1} << 24;
    float* out = distance.data() + row * w;
    for (std::size_t column = 0; column < w; ++column) {
      const std::int64_t squared_distance = envelope[column + 1];
      out[column] = squared_distance < kExactInFloat ? std::sqrt(float(squared_distance))
                                                     : float(std::sqrt(double(squared_distance)));
    }
  }
  return distance;
}

}  // namespace clearway::detail
