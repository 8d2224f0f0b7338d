#pragma once

// A minimal parallel loop for the engine's embarrassingly parallel stages (per scan line, per
// plane, per half of the map). Chunks are contiguous so results can be gathered in order. The
// extra threads live in a small pool that is started once: a pipeline run makes ten or so parallel
// calls, and starting threads for each cost about a millisecond.

#include <algorithm>
#include <cstddef>
#include <exception>
#include <functional>
#include <memory>
#include <vector>

namespace clearway::detail {

// Cache lines are this long on the x86-64 and ARM cores Clearway runs on [bytes].
inline constexpr std::size_t kCacheLine = 64;

// One result per part of a parallel loop (parallelChunks' `chunk`), each on cache lines of its
// own. Parts that keep writing their own result in one plain array (a vector's end as it grows, a
// running bound) share a cache line and take it from each other at every write: the second
// thread then slows both down. Bounds kept in plain arrays of doubles made a loop of 0.31 ms on
// one thread take 1.1 ms on two.
template <typename T>
class PerPart {
  struct alignas(kCacheLine) Slot {
    T value{};
  };
  template <typename S, typename V>
  struct Iterator {
    S* slot;
    V& operator*() const { return slot->value; }
    Iterator& operator++() {
      ++slot;
      return *this;
    }
    bool operator==(const Iterator&) const = default;
  };

 public:
  explicit PerPart(std::size_t parts, const T& initial = T{}) : slots_(parts, Slot{initial}) {}
  std::size_t size() const { return slots_.size(); }
  T& operator[](std::size_t part) { return slots_[part].value; }
  const T& operator[](std::size_t part) const { return slots_[part].value; }
  T& front() { return slots_.front().value; }
  Iterator<Slot, T> begin() { return {slots_.data()}; }
  Iterator<Slot, T> end() { return {slots_.data() + slots_.size()}; }
  Iterator<const Slot, const T> begin() const { return {slots_.data()}; }
  Iterator<const Slot, const T> end() const { return {slots_.data() + slots_.size()}; }

 private:
  std::vector<Slot> slots_;
};

// Runs every task, some on the pool's threads and the first on the caller's, and returns when all
// have finished. Safe from several threads at once; a call made from a pool thread runs inline.
void runTasks(std::vector<std::function<void()>>& tasks);

// A task started on the pool that the caller joins later, doing other work meanwhile: work whose
// result is needed only later in a run (the staircases, the scanner's view) then fills the
// stretches where the other thread would wait for serial work. The caller helps with queued work
// while it waits. With one thread, or from a pool thread, the task runs when joined, on the
// caller's thread: the run does its work in the order it would without it (and its memory peaks
// as it did). join() rethrows the task's error; the destructor waits for a started task, so that
// what it refers to outlives it, and drops one never joined.
class BackgroundTask {
 public:
  BackgroundTask(std::function<void()> task, int threads);
  ~BackgroundTask();
  BackgroundTask(const BackgroundTask&) = delete;
  BackgroundTask& operator=(const BackgroundTask&) = delete;
  void join();

  struct State;

 private:
  std::shared_ptr<State> state_;
  std::function<void()> deferred_;  // the task, when it runs at join()
  bool joined_ = false;
};

// Runs different tasks in parallel (one after the other with one thread): the first on the
// caller's thread, which then helps with the others. Rethrows the first error, in task order.
inline void parallelTasks(std::vector<std::function<void()>> tasks, int threads) {
  std::vector<std::exception_ptr> errors(tasks.size());
  for (std::size_t t = 0; t < tasks.size(); ++t)
    tasks[t] = [task = std::move(tasks[t]), &error = errors[t]] {
      try {
        task();
      } catch (...) {
        error = std::current_exception();
      }
    };
  if (threads > 1) {
    runTasks(tasks);
  } else {
    for (auto& task : tasks)
      task();
  }
  for (const std::exception_ptr& error : errors)
    if (error) std::rethrow_exception(error);
}

// How many contiguous parts parallelChunks cuts [0, count) into: `parts_per_thread` per thread
// when several threads run, else one.
inline std::size_t chunkCount(std::size_t count, int threads, std::size_t parts_per_thread = 1) {
  const std::size_t wanted = threads > 1 ? std::size_t(threads) * parts_per_thread : 1;
  return std::max<std::size_t>(1, std::min(count, wanted));
}

// Calls work(begin, end, chunk) for chunkCount(count, threads, parts_per_thread) contiguous parts
// of [0, count), in parallel. More parts than threads balance work that is uneven along the range
// (the threads take the parts as they finish), at the cost of one task each.
template <typename Work>
void parallelChunks(std::size_t count, int threads, Work&& work, std::size_t parts_per_thread = 1) {
  const std::size_t chunks = chunkCount(count, threads, parts_per_thread);
  if (chunks == 1) {
    work(std::size_t{0}, count, std::size_t{0});
    return;
  }
  std::vector<std::function<void()>> tasks;
  for (std::size_t c = 0; c < chunks; ++c) {
    const std::size_t begin = count * c / chunks, end = count * (c + 1) / chunks;
    tasks.emplace_back([&work, begin, end, c] { work(begin, end, c); });
  }
  parallelTasks(std::move(tasks), threads);
}

}  // namespace clearway::detail
