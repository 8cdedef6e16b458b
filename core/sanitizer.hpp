#pragma once
// WARPFEM_ADDRESS_SANITIZER is 1 in builds with AddressSanitizer (scripts/build.sh
// --sanitize), else 0. GCC defines __SANITIZE_ADDRESS__; Clang has __has_feature.

#if defined(__SANITIZE_ADDRESS__)
#define WARPFEM_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define WARPFEM_ADDRESS_SANITIZER 1
#endif
#endif
#ifndef WARPFEM_ADDRESS_SANITIZER
#define WARPFEM_ADDRESS_SANITIZER 0
#endif
