#pragma once
// What every libFuzzer target here shares: MPI and PETSc started once per
// process, a private folder for the input files the readers under test open,
// and the rule that bad input may only end in warpfem::Error.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "core/error.hpp"

namespace warpfem::fuzz {

/// Starts MPI and PETSc once for this process (without libFuzzer's arguments,
/// which PETSc would otherwise read as its options) and silences logging.
void start_environment();

/// Writes `size` bytes to `name` in this process's private folder (created on
/// first use, removed at exit) and returns the file's path.
std::string write_input(const std::string& name, const std::uint8_t* data, std::size_t size);

/// The input as text.
inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

/// Runs `body`. A refusal (warpfem::Error) is a correct answer to bad input;
/// any other exception escapes and libFuzzer reports it as a crash.
template <class Body>
void refused_or_accepted(Body&& body) {
  try {
    body();
  } catch (const Error&) {
  }
}

}  // namespace warpfem::fuzz
