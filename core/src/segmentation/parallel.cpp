#include "parallel.h"

#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>
#include <utility>

namespace clearway::detail {

struct BackgroundTask::State {
  bool done = false;
  std::condition_variable finished;
  std::exception_ptr error;
};

namespace {

// Workers that wait for tasks; one call's tasks share a counter the caller waits on.
class Pool {
 public:
  Pool() {
    const unsigned cores = std::max(2U, std::thread::hardware_concurrency());
    for (unsigned i = 1; i < cores; ++i)
      workers_.emplace_back([this] { serve(); });
  }
  ~Pool() {
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    for (std::thread& worker : workers_)
      worker.join();
  }

  void run(std::vector<std::function<void()>>& tasks) {
    struct Batch {
      std::size_t remaining = 0;
      std::condition_variable done;
    } batch;
    {
      std::lock_guard lock(mutex_);
      batch.remaining = tasks.size() - 1;
      for (std::size_t t = 1; t < tasks.size(); ++t)
        queue_.push_back([&batch, &task = tasks[t], this] {
          task();
          std::lock_guard finished(mutex_);
          if (--batch.remaining == 0) batch.done.notify_all();
        });
    }
    wake_.notify_all();
    tasks.front()();
    // Help with queued work while waiting, so a busy pool never stalls a caller.
    std::unique_lock lock(mutex_);
    helpUntil(lock, batch.done, [&batch] { return batch.remaining == 0; });
  }

  // Queues `task`; `state` says when it is done.
  void start(const std::shared_ptr<BackgroundTask::State>& state, std::function<void()> task) {
    {
      std::lock_guard lock(mutex_);
      queue_.push_back([state, task = std::move(task), this] {
        try {
          task();
        } catch (...) {
          state->error = std::current_exception();
        }
        std::lock_guard finished(mutex_);
        state->done = true;
        state->finished.notify_all();
      });
    }
    wake_.notify_one();
  }

  // Waits until `state` is done, helping with queued work meanwhile (the task itself, if no
  // worker has taken it yet).
  void join(BackgroundTask::State& state) {
    std::unique_lock lock(mutex_);
    helpUntil(lock, state.finished, [&state] { return state.done; });
  }

  static bool onWorker() { return on_worker_; }

 private:
  // Runs queued work until `finished()` holds, waiting on `done` while the queue is empty.
  // `lock` holds mutex_.
  template <typename Finished>
  void helpUntil(std::unique_lock<std::mutex>& lock, std::condition_variable& done,
                 Finished finished) {
    while (!finished()) {
      if (!queue_.empty()) {
        auto next = std::move(queue_.front());
        queue_.pop_front();
        lock.unlock();
        next();
        lock.lock();
      } else {
        done.wait(lock);
      }
    }
  }

  void serve() {
    on_worker_ = true;
    std::unique_lock lock(mutex_);
    while (true) {
      wake_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
      if (stopping_ && queue_.empty()) return;
      auto task = std::move(queue_.front());
      queue_.pop_front();
      lock.unlock();
      task();
      lock.lock();
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> queue_;
  std::vector<std::thread> workers_;
  bool stopping_ = false;
  static thread_local bool on_worker_;
};

thread_local bool Pool::on_worker_ = false;

Pool& pool() {
  static Pool threads;
  return threads;
}

}  // namespace

void runTasks(std::vector<std::function<void()>>& tasks) {
  if (tasks.empty()) return;
  if (tasks.size() == 1 || Pool::onWorker()) {
    for (auto& task : tasks)
      task();
    return;
  }
  pool().run(tasks);
}

BackgroundTask::BackgroundTask(std::function<void()> task, int threads)
    : state_(std::make_shared<State>()) {
  if (threads > 1 && !Pool::onWorker()) {
    pool().start(state_, std::move(task));
  } else {
    deferred_ = std::move(task);
  }
}

BackgroundTask::~BackgroundTask() {
  if (!joined_ && !deferred_) pool().join(*state_);
}

void BackgroundTask::join() {
  joined_ = true;
  if (deferred_) {
    std::exchange(deferred_, nullptr)();
    return;
  }
  pool().join(*state_);
  if (state_->error) std::rethrow_exception(state_->error);
}

}  // namespace clearway::detail
