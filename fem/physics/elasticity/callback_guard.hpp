#pragma once
// Exceptions must not cross PETSc's C frames. A PETSc callback runs its body
// through CallbackGuard::run(): an exception is stored and PETSC_ERR_USER is
// returned instead; after the PETSc call returns, rethrow_if_failed() rethrows
// the original exception (so users see the warpfem::Error, not a PETSc trace).

#include <petscsys.h>

#include <exception>
#include <utility>

namespace warpfem::fem {

class CallbackGuard {
 public:
  template <class F>
  PetscErrorCode run(F&& body) noexcept {
    try {
      std::forward<F>(body)();
      return 0;
    } catch (...) {
      if (!error_) error_ = std::current_exception();
      return PETSC_ERR_USER;
    }
  }
  bool failed() const { return static_cast<bool>(error_); }
  /// Rethrows (and clears) the stored exception, if any.
  void rethrow_if_failed() {
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  }

 private:
  std::exception_ptr error_;
};

}  // namespace warpfem::fem
