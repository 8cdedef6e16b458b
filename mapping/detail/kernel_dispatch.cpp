#include <atomic>
#include <cstdlib>
#include <cstring>

#include "core/log.hpp"
#include "mapping/detail/mean_value_avx512.hpp"

namespace warpfem::mapping::detail {
namespace {

bool cpu_and_environment_allow() {
  if (const char* env = std::getenv("WARPFEM_KERNELS"); env && *env) {
    if (std::strcmp(env, "portable") == 0) return false;
    log::warning("WARPFEM_KERNELS=", env,
                 " is not understood and is ignored (the only value is \"portable\")");
  }
#if defined(WARPFEM_HAVE_AVX512_KERNELS)
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f");
#else
  return false;
#endif
}

std::atomic<int>& state() {
  static std::atomic<int> s{cpu_and_environment_allow() ? 1 : 0};
  return s;
}

}  // namespace

bool avx512_kernels_enabled() {
  return state().load(std::memory_order_relaxed) != 0;
}

bool set_avx512_kernels_enabled(bool enabled) {
#if !defined(WARPFEM_HAVE_AVX512_KERNELS)
  enabled = false;
#else
  __builtin_cpu_init();
  enabled = enabled && __builtin_cpu_supports("avx512f");
#endif
  return state().exchange(enabled ? 1 : 0) != 0;
}

}  // namespace warpfem::mapping::detail
