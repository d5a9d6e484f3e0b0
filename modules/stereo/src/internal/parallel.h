// Splits rows 0..n−1 into `threads` contiguous blocks run concurrently.
#pragma once

#include <algorithm>
#include <thread>
#include <vector>

namespace specht::stereo::internal {

template <class F>
void ParallelRows(int n, int threads, const F& f) {
  threads = std::clamp(threads, 1, std::max(1, n));
  std::vector<std::thread> workers;
  auto block = [&](int t) {
    for (int y = n * t / threads; y < n * (t + 1) / threads; ++y) f(y);
  };
  for (int t = 1; t < threads; ++t) workers.emplace_back(block, t);
  block(0);
  for (auto& w : workers) w.join();
}

}  // namespace specht::stereo::internal
