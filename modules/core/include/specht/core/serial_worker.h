// specht/core/serial_worker.h: one worker thread running tasks in the order they
// were posted, so that work no later step needs (the perception pipeline's OctoMap
// insertion and video frames) overlaps the caller's next steps. Wait() returns once
// every posted task ran and rethrows the first exception one threw; the destructor
// runs what is still queued, then stops. Post blocks while `max_queued` tasks wait,
// so a caller faster than the worker cannot pile up work (and memory) without end.
#pragma once

#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <utility>

namespace specht {

class SerialWorker {
 public:
  explicit SerialWorker(size_t max_queued = 4) : max_queued_(max_queued), thread_([this] { Loop(); }) {}
  ~SerialWorker() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }
  SerialWorker(const SerialWorker&) = delete;
  SerialWorker& operator=(const SerialWorker&) = delete;

  void Post(std::function<void()> task) {
    {
      std::unique_lock lock(mutex_);
      done_.wait(lock, [this] { return tasks_.size() < max_queued_; });
      tasks_.push_back(std::move(task));
    }
    wake_.notify_all();
  }

  void Wait() {
    std::unique_lock lock(mutex_);
    done_.wait(lock, [this] { return tasks_.empty() && !running_; });
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  }

 private:
  void Loop() {
    std::unique_lock lock(mutex_);
    for (;;) {
      wake_.wait(lock, [this] { return stop_ || !tasks_.empty(); });
      if (tasks_.empty()) return;  // stopping, nothing left
      std::function<void()> task = std::move(tasks_.front());
      tasks_.pop_front();
      running_ = true;
      done_.notify_all();  // room for a blocked Post
      lock.unlock();
      try {
        task();
      } catch (...) {
        lock.lock();
        if (!error_) error_ = std::current_exception();
        lock.unlock();
      }
      lock.lock();
      running_ = false;
      done_.notify_all();
    }
  }

  const size_t max_queued_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::deque<std::function<void()>> tasks_;
  bool running_ = false, stop_ = false;
  std::exception_ptr error_;
  std::thread thread_;  // last: starts after the members it uses exist
};

}  // namespace specht
