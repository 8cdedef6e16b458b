// prefault(): populating pages ahead of the first write never changes what an
// array holds, and resize_prefaulted() is resize() (value-initialized new
// elements, old ones kept) whether or not the vector has to grow.

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <numeric>
#include <vector>

#include "core/prefault.hpp"

using namespace warpfem;

TEST(Prefault, LeavesWrittenContentsAsTheyAre) {
  constexpr std::size_t n = 3 << 20;  // 12 MB of int32: well above the 1 MB threshold
  auto a = std::make_unique<std::int32_t[]>(n);
  for (std::size_t i = 0; i < n; i += 1021) a[i] = static_cast<std::int32_t>(i);
  prefault(a.get(), n * sizeof(std::int32_t));
  for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(a[i], i % 1021 == 0 ? static_cast<std::int32_t>(i) : 0) << i;
  prefault(a.get() + 1, 100);  // small and unaligned ranges are fine too
  prefault(nullptr, 1 << 22);
}

TEST(Prefault, ResizePrefaultedIsResize) {
  for (const std::size_t grow : {std::size_t{10}, std::size_t{1} << 20, std::size_t{3} << 20}) {
    std::vector<double> v(1000);
    std::iota(v.begin(), v.end(), 1.0);
    std::vector<double> w = v;
    resize_prefaulted(v, v.size() + grow);
    w.resize(w.size() + grow);
    EXPECT_EQ(v, w) << "grow by " << grow;
    resize_prefaulted(v, 500);  // shrinking keeps the first elements
    w.resize(500);
    EXPECT_EQ(v, w);
  }
}
