// huge_page_tunables(): the restart appends glibc.malloc.hugetlb=1 to the
// user's tunables, keeps theirs, and never restarts twice or over the user's
// own choice. (Every app test runs through the restart itself.)

#include <gtest/gtest.h>

#include "core/huge_pages.hpp"

namespace warpfem {
namespace {

TEST(HugePages, TunableIsSetWhenNoneIs) {
  EXPECT_EQ(huge_page_tunables(nullptr), "glibc.malloc.hugetlb=1");
  EXPECT_EQ(huge_page_tunables(""), "glibc.malloc.hugetlb=1");
}

TEST(HugePages, OtherTunablesAreKept) {
  EXPECT_EQ(huge_page_tunables("glibc.malloc.arena_max=2"),
            "glibc.malloc.arena_max=2:glibc.malloc.hugetlb=1");
}

TEST(HugePages, NoRestartOnceTheTunableIsThere) {
  // After the restart, and when the user chose a value (0 turns huge pages off).
  EXPECT_TRUE(huge_page_tunables("glibc.malloc.hugetlb=1").empty());
  EXPECT_TRUE(huge_page_tunables("glibc.malloc.hugetlb=0").empty());
  EXPECT_TRUE(huge_page_tunables("glibc.malloc.arena_max=2:glibc.malloc.hugetlb=0").empty());
}

}  // namespace
}  // namespace warpfem
