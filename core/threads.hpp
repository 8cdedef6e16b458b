#pragma once
// Shared-memory parallelism for batched point kernels (map evaluation).
//
// The number of threads defaults to the hardware threads divided by the MPI
// ranks of MPI_COMM_WORLD (so `mpiexec -n 2` on two cores runs one thread per
// rank); WARPFEM_THREADS overrides it.

#include <functional>

#include "core/types.hpp"

namespace warpfem {

/// Threads used by parallel_for (>= 1).
int thread_count();
void set_thread_count(int threads);

/// Calls body(begin, end) on disjoint ranges covering [0, n), in parallel when
/// n is at least `grain` per thread. Ranges (each ≥ grain, except the last) are
/// handed out dynamically, so a thread may get several, in any order; the
/// calling thread works too. Exceptions from any range are rethrown.
/// A parallel_for called from inside another one's body runs serially.
void parallel_for(Index n, Index grain, const std::function<void(Index, Index)>& body);

}  // namespace warpfem
