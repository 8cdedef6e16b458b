#pragma once
// What a refused call says: the message of the warpfem::Error it throws.

#include <functional>
#include <string>

#include "core/error.hpp"

namespace warpfem::test {

/// The message of the warpfem::Error that `f` throws, or "(no error)".
inline std::string error_text(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace warpfem::test
