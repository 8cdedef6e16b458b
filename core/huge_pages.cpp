#include "core/huge_pages.hpp"

#include <cstdlib>
#include <cstring>
#include <fstream>

#include "core/sanitizer.hpp"

#if defined(__linux__) && defined(__GLIBC__)
#include <gnu/libc-version.h>
#include <sys/auxv.h>
#include <unistd.h>
#endif

namespace warpfem {

std::string huge_page_tunables(const char* current) {
  constexpr const char* kTunable = "glibc.malloc.hugetlb";
  if (current == nullptr || *current == '\0') return std::string(kTunable) + "=1";
  if (std::strstr(current, kTunable) != nullptr) return {};
  return std::string(current) + ":" + kTunable + "=1";
}

#if defined(__linux__) && defined(__GLIBC__)
namespace {

bool glibc_has_hugetlb_tunable() {
  char* end = nullptr;
  const long major = std::strtol(gnu_get_libc_version(), &end, 10);
  const long minor = end != nullptr && *end == '.' ? std::strtol(end + 1, nullptr, 10) : 0;
  return major > 2 || (major == 2 && minor >= 35);
}

/// True when the kernel gives huge pages only to ranges that ask for them
/// ("always" needs no tunable, "never" ignores it).
bool transparent_huge_pages_on_request() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  std::getline(in, modes);
  return modes.find("[madvise]") != std::string::npos;
}

/// False for a set-user-id start (glibc may drop the tunable again: no endless
/// restarts) and for a start through the dynamic loader (`ld.so warpfem ...`:
/// /proc/self/exe is then the loader, which the kernel started without an
/// interpreter, so AT_BASE is 0).
bool restart_is_safe() {
  return getauxval(AT_SECURE) == 0 && getauxval(AT_BASE) != 0;
}

}  // namespace

void restart_with_huge_pages(char** argv) {
  if (WARPFEM_ADDRESS_SANITIZER || argv == nullptr || !restart_is_safe()) return;
  const std::string tunables = huge_page_tunables(std::getenv("GLIBC_TUNABLES"));
  if (tunables.empty() || !glibc_has_hugetlb_tunable() || !transparent_huge_pages_on_request()) return;
  if (setenv("GLIBC_TUNABLES", tunables.c_str(), 1) != 0) return;
  execv("/proc/self/exe", argv);
  // Only reached if the restart failed: go on as we are. The variable stays
  // set, so no child started later tries again.
}
#else
void restart_with_huge_pages(char** argv) {
  (void)argv;
}
#endif

}  // namespace warpfem
