#pragma once
// Rank-local work inside a parallel run (rank 0 creating a directory or writing an
// index file) must not fail on one rank alone: the other ranks would wait forever in
// the next collective call. run_collectively() turns a local failure into the same
// warpfem::Error on every rank.

#include <mpi.h>

#include <functional>

namespace warpfem {

/// Runs `work` on this rank (it may do nothing on most ranks), then agrees with every rank
/// of `comm` on the outcome. If `work` threw on any rank, every rank throws the same
/// warpfem::Error: the one of the lowest failing rank (other exceptions become an Error with
/// their what()). Collective: every rank of `comm` must call it.
void run_collectively(MPI_Comm comm, const std::function<void()>& work);

}  // namespace warpfem
