#pragma once

// Timing helpers shared by `clearway-cli bench` and its peers.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

namespace clearway::cli {

// The q-quantile of `values` by the nearest-rank rule (q = 0.5 is the median, 0.95 the p95).
inline double quantile(std::vector<double> values, double q) {
  std::sort(values.begin(), values.end());
  const auto rank = std::size_t(std::ceil(q * double(values.size())));
  return values[std::clamp<std::size_t>(rank, 1, values.size()) - 1];
}

// Runs `work` once to warm up, then `repeat` times; the wall time of each timed run [ms].
template <typename Work>
std::vector<double> timeRuns(int repeat, Work&& work) {
  work();
  std::vector<double> milliseconds;
  for (int run = 0; run < repeat; ++run) {
    const auto start = std::chrono::steady_clock::now();
    work();
    milliseconds.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count());
  }
  return milliseconds;
}

}  // namespace clearway::cli
