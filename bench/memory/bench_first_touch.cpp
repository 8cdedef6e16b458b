// The cost of first writes to fresh memory, per MB: 4 KiB pages, 4 KiB pages
// populated ahead by madvise(MADV_POPULATE_WRITE) (what prefault() does), and
// 2 MiB transparent huge pages by madvise(MADV_HUGEPAGE) (what glibc's malloc
// does under glibc.malloc.hugetlb=1, core/huge_pages.hpp). Each variant maps
// a fresh anonymous range, writes one byte per 4 KiB and unmaps it, `rounds`
// times; the first huge-page round of a process can include the kernel's
// compaction of free memory into 2 MiB blocks.
//
//   build/bench/memory/bench_first_touch [megabytes] [rounds]   (defaults: 512, 3)

#include <sys/mman.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace {

double touch_ms_per_mb(std::size_t bytes, int advice) {
  void* map = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (map == MAP_FAILED) {
    std::perror("mmap");
    std::exit(1);
  }
  char* p = static_cast<char*>(map);
  const auto start = std::chrono::steady_clock::now();
  if (advice == 1) madvise(p, bytes, MADV_POPULATE_WRITE);
  if (advice == 2) madvise(p, bytes, MADV_HUGEPAGE);
  for (std::size_t i = 0; i < bytes; i += 4096) p[i] = 1;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  munmap(map, bytes);
  return seconds * 1e3 / static_cast<double>(bytes >> 20);
}

}  // namespace

int main(int argc, char** argv) {
  const long mb = argc > 1 ? std::atol(argv[1]) : 512;
  const int rounds = argc > 2 ? std::atoi(argv[2]) : 3;
  if (mb <= 0 || rounds <= 0) {
    std::fprintf(stderr, "usage: bench_first_touch [megabytes > 0] [rounds > 0]\n");
    return 2;
  }
  const std::size_t bytes = static_cast<std::size_t>(mb) << 20;
  const char* names[] = {"4 KiB pages", "4 KiB pages, MADV_POPULATE_WRITE", "2 MiB pages, MADV_HUGEPAGE"};
  std::printf("first write to %ld MB of fresh memory, ms per MB, %d rounds\n", mb, rounds);
  for (int advice = 0; advice < 3; ++advice) {
    std::printf("%-34s", names[advice]);
    for (int r = 0; r < rounds; ++r) std::printf(" %7.3f", touch_ms_per_mb(bytes, advice));
    std::printf("\n");
  }
  return 0;
}
