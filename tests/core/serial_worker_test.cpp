// The worker runs tasks in posting order, one at a time, and hands their results and
// their first exception back at Wait(); run under ThreadSanitizer too.
#include "specht/core/serial_worker.h"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <vector>

namespace specht {
namespace {

TEST(SerialWorkerTest, TasksRunInOrderOneAtATime) {
  SerialWorker worker;
  std::vector<int> order;  // written by the worker only, read after Wait
  std::atomic<int> running{0}, overlapped{0};
  for (int i = 0; i < 200; ++i)
    worker.Post([&, i] {
      if (running.fetch_add(1) != 0) overlapped.fetch_add(1);
      order.push_back(i);
      running.fetch_sub(1);
    });
  worker.Wait();
  ASSERT_EQ(order.size(), 200u);
  for (int i = 0; i < 200; ++i) EXPECT_EQ(order[i], i);
  EXPECT_EQ(overlapped.load(), 0);
  worker.Post([&] { order.push_back(200); });
  worker.Wait();
  EXPECT_EQ(order.back(), 200);
}

TEST(SerialWorkerTest, TheFirstExceptionComesBackAtWaitAndLaterTasksStillRun) {
  SerialWorker worker;
  int after = 0;
  worker.Post([] { throw std::runtime_error("first"); });
  worker.Post([] { throw std::runtime_error("second"); });
  worker.Post([&] { after = 1; });
  try {
    worker.Wait();
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "first");
  }
  EXPECT_EQ(after, 1);
  EXPECT_NO_THROW(worker.Wait());  // reported once
}

TEST(SerialWorkerTest, PostWaitsWhileTheQueueIsFull) {
  SerialWorker worker(2);
  std::atomic<int> most_waiting{0}, posted{0}, ran{0};
  for (int i = 0; i < 40; ++i) {
    worker.Post([&] {
      ran.fetch_add(1);
      const int waiting = posted.load() - ran.load();
      if (waiting > most_waiting.load()) most_waiting.store(waiting);
    });
    posted.fetch_add(1);
  }
  worker.Wait();
  EXPECT_EQ(ran.load(), 40);
  EXPECT_LE(most_waiting.load(), 3);  // two queued, one just posted
}

TEST(SerialWorkerTest, TheDestructorRunsWhatIsQueued) {
  std::atomic<int> ran{0};
  {
    SerialWorker worker;
    for (int i = 0; i < 50; ++i) worker.Post([&] { ran.fetch_add(1); });
  }
  EXPECT_EQ(ran.load(), 50);
}

}  // namespace
}  // namespace specht
