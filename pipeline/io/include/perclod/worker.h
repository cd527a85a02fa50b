// perclod's one background-thread mechanism (private to the pipeline): a
// thread that runs the tasks handed to it in order. The labelling and judging
// passes keep one per pass; ImageWriter (perclod/image_io.h) encodes PNGs on
// one.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <thread>
#include <type_traits>

namespace perclod::detail {

// Each task's result (or exception) comes back in its future. Unlike a
// std::async per task, the thread outlives the tasks, so the scratch
// perception keeps per thread (the DWT's and the FIR filter's, a few MB a
// view) is allocated once per worker, not page-faulted afresh for every view.
// The destructor finishes the queued tasks, then joins.
class Worker {
 public:
  Worker() : thread_([this] { loop(); }) {}
  ~Worker() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_one();
    thread_.join();
  }
  Worker(const Worker&) = delete;
  Worker& operator=(const Worker&) = delete;

  template <class F>
  std::future<std::invoke_result_t<F&>> submit(F f) {
    auto task = std::make_shared<std::packaged_task<std::invoke_result_t<F&>()>>(std::move(f));
    auto result = task->get_future();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      queue_.emplace_back([task] { (*task)(); });
    }
    wake_.notify_one();
    return result;
  }

 private:
  void loop() {
    for (;;) {
      std::function<void()> task;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [this] { return stop_ || !queue_.empty(); });
        if (queue_.empty()) return;  // stopped, nothing left
        task = std::move(queue_.front());
        queue_.pop_front();
      }
      task();  // a packaged_task: an exception goes to its future
    }
  }
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> queue_;
  bool stop_ = false;
  std::thread thread_;  // last: started once the members above exist
};

}  // namespace perclod::detail
