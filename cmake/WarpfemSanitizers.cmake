# Instrumented builds, each in a build folder of its own (the normal build is unaffected):
#   WARPFEM_SANITIZE  AddressSanitizer + UndefinedBehaviorSanitizer on every target (GCC or Clang);
#                     the test suite runs under it (scripts/build.sh --sanitize, build-asan/).
#   WARPFEM_BUILD_FUZZ libFuzzer targets in tests/fuzz (Clang only); implies the sanitizers and
#                     adds libFuzzer's coverage instrumentation to every library (scripts/fuzz.sh).
# Undefined behaviour aborts (no recovery), so a test or fuzz run cannot pass over it.

if(WARPFEM_BUILD_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "warpfem: WARPFEM_BUILD_FUZZ needs Clang (libFuzzer): configure with "
                        "-DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang, or use scripts/fuzz.sh")
  endif()
  set(WARPFEM_SANITIZE ON)
endif()

if(WARPFEM_SANITIZE)
  set(warpfem_sanitizers -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
  add_compile_options(${warpfem_sanitizers})
  add_link_options(-fsanitize=address,undefined)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    # The instrumentation keeps Clang from vectorizing the loops marked for it,
    # and it says so for each: expected in this build, nothing to act on.
    add_compile_options(-Wno-pass-failed)
  endif()
  if(WARPFEM_BUILD_FUZZ)
    add_compile_options(-fsanitize=fuzzer-no-link)
  endif()
endif()
