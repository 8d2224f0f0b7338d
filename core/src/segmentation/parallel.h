#pragma once

// A minimal parallel loop for the engine's embarrassingly parallel stages (per scan line, per
// orientation). Chunks are contiguous so results can be gathered in order.

#include <algorithm>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace clearway::detail {

// Calls work(begin, end, chunk) for `chunks` contiguous parts of [0, count), in parallel.
template <typename Work>
void parallelChunks(std::size_t count, int threads, Work&& work) {
  const std::size_t chunks =
      std::max<std::size_t>(1, std::min<std::size_t>(count, std::size_t(std::max(threads, 1))));
  if (chunks == 1) {
    work(std::size_t{0}, count, std::size_t{0});
    return;
  }
  std::vector<std::thread> workers;
  std::vector<std::exception_ptr> errors(chunks);
  for (std::size_t c = 0; c < chunks; ++c) {
    const std::size_t begin = count * c / chunks, end = count * (c + 1) / chunks;
    workers.emplace_back([&, begin, end, c] {
      try {
        work(begin, end, c);
      } catch (...) {
        errors[c] = std::current_exception();
      }
    });
  }
  for (std::thread& worker : workers)
    worker.join();
  for (const std::exception_ptr& error : errors)
    if (error) std::rethrow_exception(error);
}

}  // namespace clearway::detail
