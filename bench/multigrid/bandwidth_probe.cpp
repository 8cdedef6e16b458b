// How much memory bandwidth N ranks get together, against one rank alone.
//
// A multigrid solve streams its matrices and vectors (about 14 GB/s on one
// core here), so its speed-up on N ranks of one machine is capped by the
// aggregate bandwidth they share, not by N. This probe measures that cap: each
// rank runs the STREAM triad a[i] = b[i] + s·c[i] on arrays far larger than
// the caches, first rank 0 alone, then all ranks at once (started together at
// a barrier), and reports the best of several repetitions.
//
//   mpiexec -n 2 build/bench/multigrid/bandwidth_probe [-mb 160] [-reps 15]
//
// Prints the one-rank bandwidth, the aggregate of all ranks, and their ratio:
// the largest speed-up a purely bandwidth-bound kernel can reach.

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

double option(int argc, char** argv, const char* name, double fallback) {
  for (int i = 1; i + 1 < argc; ++i)
    if (std::strcmp(argv[i], name) == 0) return std::atof(argv[i + 1]);
  return fallback;
}

/// Best triad bandwidth (GB/s, counting the two reads and the write) over
/// `reps` runs. With `together`, every run starts at a barrier of all ranks.
double triad_bandwidth(std::vector<double>& a, const std::vector<double>& b, const std::vector<double>& c,
                       int reps, bool together, MPI_Comm comm) {
  const std::size_t n = a.size();
  double best = 0;
  for (int r = 0; r < reps; ++r) {
    if (together) MPI_Barrier(comm);
    const auto start = std::chrono::steady_clock::now();
    const double s = 1.0 + 1e-3 * r;
    for (std::size_t i = 0; i < n; ++i) a[i] = b[i] + s * c[i];
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    best = std::max(best, 3.0 * sizeof(double) * static_cast<double>(n) / seconds / 1e9);
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const double mb = option(argc, argv, "-mb", 160.0);
  const int reps = std::max(1, static_cast<int>(option(argc, argv, "-reps", 15.0)));
  if (!(mb > 0)) {
    if (rank == 0) std::fprintf(stderr, "bandwidth_probe: -mb must be positive (megabytes per array)\n");
    MPI_Finalize();
    return 1;
  }
  const auto n = static_cast<std::size_t>(mb * 1e6 / sizeof(double));
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);

  // 1. Rank 0 alone while the others wait.
  double alone = 0;
  if (rank == 0) alone = triad_bandwidth(a, b, c, reps, false, MPI_COMM_WORLD);
  MPI_Barrier(MPI_COMM_WORLD);
  // 2. All ranks at once.
  const double mine = triad_bandwidth(a, b, c, reps, true, MPI_COMM_WORLD);
  double total = 0;
  MPI_Reduce(&mine, &total, 1, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
  double check = 0;
  for (std::size_t i = 0; i < n; i += 4096) check += a[i];
  double all_checks = 0;
  MPI_Reduce(&check, &all_checks, 1, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
  if (rank == 0) {
    std::printf("# STREAM triad, %.0f MB per array, best of %d runs (checksum %.6g)\n", mb, reps, all_checks);
    std::printf("one rank alone:        %6.1f GB/s\n", alone);
    std::printf("%2d ranks together:     %6.1f GB/s in total (%.1f per rank)\n", size, total, total / size);
    std::printf("bandwidth speed-up:    %6.2fx (the cap for a bandwidth-bound kernel on %d ranks)\n",
                total / alone, size);
  }
  MPI_Finalize();
  return 0;
}
