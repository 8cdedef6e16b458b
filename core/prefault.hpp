#pragma once
// First-touch cost of large fresh arrays. On Linux the first write to each
// 4 KiB page of a fresh allocation traps into the kernel, which then zeroes
// and maps the page; on the VMs measured here that trap costs more than the
// zeroing itself (figures in BENCHMARKS.md). prefault() asks the kernel to
// back a whole range in one call (madvise MADV_POPULATE_WRITE, Linux ≥ 5.14);
// it never changes the contents, pages already present stay as they are, and
// on other systems or small ranges it does nothing.

#include <cstddef>
#include <vector>

namespace warpfem {

/// Backs the whole pages inside [data, data + bytes) with memory now. Worth it
/// for fresh arrays of a megabyte and more that are about to be written.
void prefault(void* data, std::size_t bytes);

/// v.resize(n), with the new elements' pages populated first when they are
/// fresh memory (v grows past its capacity): one system call instead of one
/// page fault per 4 KiB. The new elements are value-initialized as by resize.
template <class T>
void resize_prefaulted(std::vector<T>& v, std::size_t n) {
  if (n > v.capacity()) {
    v.reserve(n);
    prefault(v.data() + v.size(), (n - v.size()) * sizeof(T));
  }
  v.resize(n);
}

}  // namespace warpfem
