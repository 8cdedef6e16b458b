#pragma once
// Transparent huge pages for the whole process. A run touches gigabytes of
// fresh memory (mesh levels, geometry, matrices, VTK's arrays); with 4 KiB
// pages every first write traps into the kernel, and on virtual machines that
// trap costs far more than the zeroing itself (figures in BENCHMARKS.md).
// glibc's malloc asks for 2 MiB pages when started with the tunable
// glibc.malloc.hugetlb=1 (glibc ≥ 2.35), but tunables are read only at
// process start-up, so the executable restarts itself once with it set.

#include <string>

namespace warpfem {

/// The GLIBC_TUNABLES value a restart would set, given the current one
/// (`current`, null if unset): "glibc.malloc.hugetlb=1" appended. Empty when no
/// restart is wanted: the variable names glibc.malloc.hugetlb already (the
/// user's choice, or the restart happened).
std::string huge_page_tunables(const char* current);

/// Restarts the process in place (execv of /proc/self/exe, same pid and
/// arguments) with huge_page_tunables() set, when that helps: Linux, glibc ≥
/// 2.35, transparent huge pages in "madvise" mode, no AddressSanitizer (it has
/// its own malloc), the tunable not yet set, started neither through the
/// dynamic loader nor set-user-id. Otherwise, or if the restart
/// fails, it returns and the process goes on with 4 KiB pages. Call it first
/// in main, before MPI or threads start; setting glibc.malloc.hugetlb=0 in the
/// environment turns it off.
void restart_with_huge_pages(char** argv);

}  // namespace warpfem
