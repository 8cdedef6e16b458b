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
  const int threads =
      static_cast<int>(std::min<Index>(thread_count(), std::max<Index>(1, n / std::max<Index>(1, grain))));
  if (threads <= 1 || t_inside_parallel_region) {  // nested calls run serially in their worker
    if (n > 0) body(0, n);
    return;
  }
  std::vector<std::thread> pool;
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(threads));
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      t_inside_parallel_region = true;
      try {
        const Index begin = n * t / threads, end = n * (t + 1) / threads;
        if (end > begin) body(begin, end);
      } catch (...) {
        errors[static_cast<std::size_t>(t)] = std::current_exception();
      }
    });
  for (auto& th : pool) th.join();
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace warpfem
