#include "core/threads.hpp"

#include <mpi.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <exception>
#include <thread>
#include <vector>

namespace warpfem {
namespace {
std::atomic<int> g_threads{0};

int default_threads() {
  if (const char* env = std::getenv("WARPFEM_THREADS")) {
    const int t = std::atoi(env);
    if (t >= 1) return t;
  }
  int ranks = 1, initialized = 0;
  MPI_Initialized(&initialized);
  if (initialized) MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  const int hw = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return std::max(1, hw / std::max(1, ranks));
}
}  // namespace

int thread_count() {
  if (g_threads.load() == 0) g_threads = default_threads();
  return g_threads;
}

void set_thread_count(int threads) {
  g_threads = std::max(1, threads);
}

namespace {
thread_local bool t_inside_parallel_region = false;
}  // namespace

void parallel_for(Index n, Index grain, const std::function<void(Index, Index)>& body) {
  grain = std::max<Index>(1, grain);
  const int threads = static_cast<int>(std::min<Index>(thread_count(), std::max<Index>(1, n / grain)));
  if (threads <= 1 || t_inside_parallel_region) {  // nested calls run serially in their worker
    if (n > 0) body(0, n);
    return;
  }
  // Dynamic scheduling: ~8 pieces per thread taken from a shared counter, so a
  // thread slowed down by the (shared, noisy) machine does not hold up the others.
  const Index piece = std::max(grain, (n + 8 * threads - 1) / (8 * threads));
  std::atomic<Index> next{0};
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(threads));
  auto work = [&](int t) {
    const bool was_inside = t_inside_parallel_region;
    t_inside_parallel_region = true;
    try {
      for (Index begin = next.fetch_add(piece); begin < n; begin = next.fetch_add(piece))
        body(begin, std::min(n, begin + piece));
    } catch (...) {
      errors[static_cast<std::size_t>(t)] = std::current_exception();
      next = n;  // the others stop after their current piece
    }
    t_inside_parallel_region = was_inside;
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work, t);
  work(0);  // the calling thread takes part
  for (auto& th : pool) th.join();
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace warpfem
