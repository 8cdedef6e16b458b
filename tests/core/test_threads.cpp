#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "core/threads.hpp"

using namespace warpfem;

namespace {
/// True if two ranges of a parallel_for over [0, 2) ran on different threads at
/// the same time: each range waits (up to 5 s) until both have started.
bool runs_two_ranges_concurrently() {
  std::atomic<int> started{0};
  std::atomic<bool> together{true};
  parallel_for(2, 1, [&](Index begin, Index end) {
    for (Index i = begin; i < end; ++i) {
      ++started;
      const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
      while (started.load() < 2 && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
      if (started.load() < 2) together = false;
    }
  });
  return together.load();
}

/// Sets the thread count for one test and restores it.
struct ThreadCountGuard {
  int before = thread_count();
  explicit ThreadCountGuard(int threads) { set_thread_count(threads); }
  ~ThreadCountGuard() { set_thread_count(before); }
};
}  // namespace

TEST(ParallelFor, CoversTheRangeExactlyOnce) {
  const ThreadCountGuard guard(3);
  std::vector<std::atomic<int>> hits(1000);
  parallel_for(1000, 1, [&](Index begin, Index end) {
    for (Index i = begin; i < end; ++i) ++hits[static_cast<std::size_t>(i)];
  });
  for (const auto& h : hits) EXPECT_EQ(h.load(), 1);
}

TEST(ParallelFor, NestedCallsRunSeriallyInTheirWorker) {
  const ThreadCountGuard guard(2);
  std::mutex m;
  std::set<std::thread::id> outer_threads;
  std::atomic<int> inner_total{0}, inner_foreign{0};
  parallel_for(4, 1, [&](Index begin, Index end) {
    const auto me = std::this_thread::get_id();
    {
      std::lock_guard<std::mutex> lock(m);
      outer_threads.insert(me);
    }
    for (Index i = begin; i < end; ++i)
      parallel_for(100, 1, [&](Index b, Index e) {
        inner_total += static_cast<int>(e - b);
        if (std::this_thread::get_id() != me) ++inner_foreign;  // a nested pool would run elsewhere
      });
  });
  EXPECT_GE(outer_threads.size(), 1u);
  EXPECT_EQ(inner_total.load(), 400);
  EXPECT_EQ(inner_foreign.load(), 0);
}

TEST(ParallelFor, RethrowsAnExceptionFromAWorker) {
  const ThreadCountGuard guard(2);
  EXPECT_THROW(parallel_for(10, 1,
                            [](Index begin, Index) {
                              if (begin == 0) throw std::runtime_error("range 0 failed");
                            }),
               std::runtime_error);
}

TEST(ParallelFor, RunsRangesOnSeveralThreads) {
  const ThreadCountGuard guard(2);
  EXPECT_TRUE(runs_two_ranges_concurrently());
}

TEST(ParallelFor, TheCallerIsParallelAgainAfterARegion) {
  const ThreadCountGuard guard(2);
  parallel_for(8, 1, [](Index, Index) {});  // the caller works inside, then leaves the region
  EXPECT_TRUE(runs_two_ranges_concurrently());
}

TEST(ParallelFor, SerialWithOneThread) {
  const ThreadCountGuard guard(1);
  std::atomic<int> calls{0};
  parallel_for(1000, 1, [&](Index begin, Index end) {
    ++calls;
    EXPECT_EQ(begin, 0);
    EXPECT_EQ(end, 1000);
  });
  EXPECT_EQ(calls.load(), 1);
}
