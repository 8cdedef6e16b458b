#pragma once
// How a failed `warpfem` process ends, serial or under MPI, so that every error ends
// every rank, is printed once, and the exit code is non-zero.
//
// Under MPI an error may be found by every rank at once (a config error, or a write
// failure made collective by warpfem::run_collectively) or by one rank alone while the others
// wait for it in a collective call. The two cannot be told apart where the exception is
// caught, so the ranks that fail meet on a communicator of their own with a non-blocking
// barrier: if every rank arrives within a grace period, rank 0 prints the message once and
// all return normally; otherwise the error is local, the rank prints it and calls
// MPI_Abort, which ends every rank (waiting ranks cannot be woken any other way).

#include <mpi.h>

#include <string>

namespace warpfem::apps {

class FatalErrorHandler {
 public:
  /// Collective over MPI_COMM_WORLD (duplicates it). Create after warpfem::Environment.
  explicit FatalErrorHandler(double grace_seconds = 10.0);
  ~FatalErrorHandler();
  FatalErrorHandler(const FatalErrorHandler&) = delete;
  FatalErrorHandler& operator=(const FatalErrorHandler&) = delete;

  /// Reports `message` (without an "error: " prefix) as described above and returns the exit
  /// code 1, or does not return (MPI_Abort) if the other ranks do not report an error too.
  int fail(const std::string& message);

 private:
  MPI_Comm comm_ = MPI_COMM_NULL;
  double grace_seconds_;
};

}  // namespace warpfem::apps
